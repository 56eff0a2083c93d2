"""The docs stay small and their references true (issue 30 item 6): README.md and
docs/*.md at most MAX_DOC_LINES lines together; every docs/<name>.md the repository
names exists; every link between the docs resolves (file and #anchor); every
section a file names as docs/<name>.md, "Section" is a heading of that page."""
import glob
import os
import re

import pytest

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
MAX_DOC_LINES = 3000
SKIP_DIRS = {'.git', '.ws', '.hypothesis', 'results', 'build', 'devel'}
TEXT_ENDINGS = ('.py', '.md', '.launch', '.test', '.xml', '.yaml', '.sh', '.txt', '.rst',
                '.cfg', '.cpp', '.rosinstall', 'Makefile', '.msg', '.srv', '.action')
DOC_NAME = re.compile(r'docs/([A-Za-z0-9_]+)\.md')
#: docs/<page>.md, "Section" / (\"Section" / 's "Section" (a comment's
#: line breaks and leading '#' removed first)
SECTION_REF = re.compile(r'(docs/[A-Za-z0-9_]+\.md|README\.md)(?:,|\'s|\s*\(|\s)\s*"([^"\n]{2,80})"')
MD_LINK = re.compile(r'\]\(([^)\s]+)\)')


def docs():
    return [os.path.join(REPO, 'README.md')] + sorted(glob.glob(os.path.join(REPO, 'docs', '*.md')))


def lines(path):
    with open(path) as stream:
        return stream.read().splitlines()


def text_files():
    """(path relative to the repository, text) of every text file that may name a doc."""
    for root, dirs, names in os.walk(REPO):
        dirs[:] = [name for name in dirs if name not in SKIP_DIRS]
        for name in names:
            if name.endswith(TEXT_ENDINGS):
                path = os.path.join(root, name)
                try:
                    with open(path) as stream:
                        yield os.path.relpath(path, REPO), stream.read()
                except UnicodeDecodeError:
                    continue


def headings(path):
    """The page's headings, as written (without the leading #s)."""
    return [line.lstrip('#').strip() for line in lines(path) if line.startswith('#')]


def anchor(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces -> '-'."""
    return re.sub(r'[^\w\- ]', '', heading.lower()).replace(' ', '-')


def test_the_docs_are_found():
    names = {os.path.basename(path) for path in docs()}
    assert {'README.md', 'DESIGN.md', 'safety.md', 'params.md'} <= names, names


def test_the_docs_stay_within_the_limit():
    counts = {os.path.relpath(path, REPO): len(lines(path)) for path in docs()}
    total = sum(counts.values())
    assert total <= MAX_DOC_LINES, (
        'README.md + docs/*.md: %d lines (at most %d): cut repetition, history and essays; '
        'per file: %s' % (total, MAX_DOC_LINES, sorted(counts.items(), key=lambda kv: -kv[1])))


def test_every_named_doc_exists():
    missing = {'%s: docs/%s.md' % (path, name) for path, text in text_files()
               for name in DOC_NAME.findall(text)
               if not os.path.exists(os.path.join(REPO, 'docs', name + '.md'))}
    assert not missing, 'files that do not exist are named: %s' % sorted(missing)


def section_exists(doc, section):
    found = headings(os.path.join(REPO, doc))
    wanted = section.lower()
    return any(heading.lower().startswith(wanted) or wanted in heading.lower()
               for heading in found)


def test_every_named_section_exists():
    missing = set()
    for path, text in text_files():
        flat = re.sub(r'\s*\n\s*#?\s*', ' ', text)
        for doc, section in SECTION_REF.findall(flat):
            if os.path.exists(os.path.join(REPO, doc)) and not section_exists(doc, section):
                missing.add('%s: %s, "%s"' % (path, doc, section))
    assert not missing, 'sections that are no heading of their page: %s' % sorted(missing)


@pytest.mark.parametrize('path', docs(), ids=lambda p: os.path.relpath(p, REPO))
def test_the_links_between_the_docs_resolve(path):
    broken = []
    for target in MD_LINK.findall('\n'.join(lines(path))):
        if re.match(r'[a-z]+:', target):
            continue
        name, _, fragment = target.partition('#')
        linked = os.path.normpath(os.path.join(os.path.dirname(path), name)) if name else path
        if not os.path.exists(linked):
            broken.append(target)
        elif fragment and linked.endswith('.md') and fragment not in {
                anchor(heading) for heading in headings(linked)}:
            broken.append(target)
    assert not broken, '%s: links that do not resolve: %s' % (os.path.relpath(path, REPO), broken)


#: a rostest file's name as the repository writes it (``mission_*.test``: a glob)
TEST_NAME = re.compile(r'(?<![\w./*$-])([A-Za-z0-9_*]+)\.test\b')


def test_every_named_rostest_exists():
    """Every ``<name>.test`` the docs, tests, scripts and launch files name is a file of
    test/rostest or test/lanes (a name with ``*`` matches one); CHANGELOG.rst is history."""
    have = [os.path.basename(path)[:-len('.test')]
            for folder in ('rostest', 'lanes') for path in glob.glob(os.path.join(REPO, 'test', folder, '*.test'))]
    missing = set()
    for path, text in text_files():
        if path in ('CHANGELOG.rst', os.path.join('test', 'unit', 'test_docs.py')):
            continue
        for name in TEST_NAME.findall(text):
            pattern = re.compile(re.escape(name).replace(r'\*', '.*') + '$')
            if not any(pattern.match(known) for known in have):
                missing.add('%s: %s.test' % (path, name))
    assert not missing, 'rostests that do not exist are named: %s' % sorted(missing)
