"""Generic helpers for the bench's output: grouping rows, medians and worst
cases, Markdown tables and CSV files."""
import csv
import math
import os
import statistics


def group(rows, *keys):
    """{tuple of ``keys`` values: [rows]}, in first-seen order."""
    groups = {}
    for row in rows:
        groups.setdefault(tuple(row[k] for k in keys), []).append(row)
    return groups


def finite(values):
    return [v for v in values if v is not None and not (isinstance(v, float) and math.isnan(v))]


def median(values):
    values = finite(values)
    return statistics.median(values) if values else float('nan')


def num(value, digits=3):
    """A number as text; '—' for None/NaN; ints without decimals."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return '—'
    if isinstance(value, int):
        return str(value)
    return '%.*f' % (digits, value)


def med_worst(values, digits=3, worst=max):
    """'median (worst)' of ``values``; ``worst`` picks the worst case (max by default)."""
    values = finite(values)
    if not values:
        return '—'
    return '%s (%s)' % (num(statistics.median(values), digits), num(worst(values), digits))


def med_range(values, digits=3):
    """'median [min..max]' of ``values``."""
    values = finite(values)
    if not values:
        return '—'
    return '%s [%s..%s]' % (num(statistics.median(values), digits), num(min(values), digits),
                            num(max(values), digits))


def farthest_from_zero(values):
    """The worst case of a signed error: the value with the largest magnitude."""
    return max(values, key=abs)


def markdown_table(header, lines):
    """A Markdown table from a header list and rows of cell texts."""
    out = ['| ' + ' | '.join(header) + ' |', '|' + '---|' * len(header)]
    out.extend('| ' + ' | '.join(str(c) for c in line) + ' |' for line in lines)
    return '\n'.join(out) + '\n'


def write_csv(path, rows, fields=None):
    """``rows`` (dicts) to ``path``; columns ``fields`` or every scalar key of the first row."""
    if fields is None:
        fields = [k for k, v in rows[0].items() if not isinstance(v, (list, tuple, dict))] if rows else []
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, 'w', newline='') as stream:
        writer = csv.DictWriter(stream, fieldnames=fields, extrasaction='ignore')
        writer.writeheader()
        for row in rows:
            writer.writerow({k: row.get(k) for k in fields})
