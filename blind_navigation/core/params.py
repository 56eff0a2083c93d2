"""Typed, frozen parameters: a :class:`Param` is one setting a user may give, a
:class:`Schema` a role's params and constants (``fixed``); validated once at start into
frozen params, or a :class:`ParamError` naming role, param, value and range."""
import math
from collections import namedtuple

#: The default of a param that the launch files set (its launch arg holds the default).
REQUIRED = type('Required', (object,), {'__repr__': lambda self: 'REQUIRED'})()


class ParamError(ValueError):
    """A param that is missing, of the wrong type or out of its range."""


class Param(namedtuple('Param', 'name default unit doc lo hi choices')):
    """One user param: ``lo``/``hi`` bound a number (inclusive, None: open), ``choices`` the
    strings allowed (a tuple default: a list of them)."""

    def __new__(cls, name, default, unit, doc, lo=None, hi=None, choices=None):
        return super(Param, cls).__new__(cls, name, default, unit, doc, lo, hi,
                                         tuple(choices) if choices else None)

    @property
    def kind(self):
        """The type of the default (a REQUIRED param: of its range)."""
        if self.default is not REQUIRED:
            return type(self.default)
        return str if self.choices else bool if self.lo is None else float

    def allowed(self):
        """What the param accepts, as the docs and the errors say it."""
        if self.choices:
            return ('a list of ' if self.kind is tuple else 'one of ') + ', '.join(self.choices)
        if self.kind is tuple:
            return 'a list of names'
        if self.kind is bool:
            return 'true or false'
        if self.kind is str:
            return 'a string'
        low = '-inf' if self.lo is None else repr(self.lo)
        high = 'inf' if self.hi is None else repr(self.hi)
        return '%s in [%s, %s]' % ('an integer' if self.kind is int else 'a number', low, high)

    def check(self, value, role, where=''):
        """``value`` as this param's type; ParamError naming role, ``where`` + param, value, range."""
        kind, ok = self.kind, False
        if kind is float and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        if kind is tuple and isinstance(value, list):
            value = tuple(value)
        if isinstance(value, kind) and not (kind is not bool and isinstance(value, bool)):
            if kind in (int, float):
                ok = (math.isfinite(value) and (self.lo is None or value >= self.lo)
                      and (self.hi is None or value <= self.hi))
            elif kind is tuple:
                ok = all(isinstance(item, str) and (self.choices is None or item in self.choices)
                         for item in value) and len(set(value)) == len(value)
            else:
                ok = self.choices is None or value in self.choices
        if not ok:
            raise ParamError('%s: param %s%s = %r is not allowed: %s%s'
                             % (role, where, self.name, value, self.allowed(),
                                ' ' + self.unit if self.unit and kind in (int, float) else ''))
        return value


class Schema(object):
    """A role's ``params``, its constants ``fixed`` ({name: value}) and the params ``shared``
    by every role of a process (``~name``, not ``~<role>/name``)."""

    def __init__(self, role, params, fixed=None, shared=()):
        self.role = role
        self.params = tuple(params)
        names = [p.name for p in self.params]
        self.fixed = {k: v for k, v in (fixed or {}).items() if k not in names}
        self.shared = tuple(name for name in shared if name in names)
        self._type = namedtuple('Params', sorted(names + list(self.fixed)))

    def __getitem__(self, name):
        return next(p for p in self.params if p.name == name)

    def validate(self, values, where=''):
        """Frozen params from ``values`` (user params; missing: the default), or a ParamError;
        ``where``: the namespace prefix the errors name (a str, or a function of the name)."""
        prefix = where if callable(where) else (lambda name: where)
        unknown = sorted(set(values) - {p.name for p in self.params})
        if unknown:
            raise ParamError('%s: unknown param %s (known: %s)' % (
                self.role, ', '.join(prefix(n) + n for n in unknown),
                ', '.join(p.name for p in self.params)))
        typed = dict(self.fixed)
        for param in self.params:
            value = values.get(param.name, param.default)
            if value is REQUIRED:
                raise ParamError('%s: param %s%s not set (the launch files set it; with rosrun '
                                 'give _%s:=...)' % (self.role, prefix(param.name), param.name, param.name))
            typed[param.name] = param.check(value, self.role, prefix(param.name))
        return self._type(**typed)

    def make(self, **overrides):
        """The defaults with ``overrides`` (fixed ones too), for tests and the simulator."""
        user = {k: v for k, v in overrides.items() if k not in self.fixed}
        return self.validate(user)._replace(**{k: v for k, v in overrides.items() if k in self.fixed})
