#!/usr/bin/python3
"""Check that every local link in README.md and docs/*.md resolves.

Usage: scripts/check_docs_links.py [ROOT]   (ROOT: the repository, default this script's ..)

A local link is a markdown link or image, [text](TARGET) or ![alt](TARGET), whose TARGET is
not a URL: a file relative to the page (it must exist), optionally with #ANCHOR (the file, a
markdown page, must have a heading that GitHub turns into that anchor), or #ANCHOR alone (a
heading of the page itself). Links inside code blocks and code spans are not links.
Exits 1 listing each broken link as FILE:LINE: problem; 0 when all resolve. Standard library
only.
"""
import os
import pathlib
import re
import sys

LINK = re.compile(r'!?\[(?:[^\]`]|`[^`]*`)*\]\(\s*<?([^)\s>]+)>?(?:\s+"[^"]*")?\s*\)')
CODE_SPAN = re.compile(r'(`+)(?:(?!\1).)+?\1')
HEADING = re.compile(r'^(#{1,6})\s+(.*?)\s*#*\s*$')
HTML_ANCHOR = re.compile(r'<a\s+(?:name|id)="([^"]+)"')
SCHEME = re.compile(r'^[a-zA-Z][a-zA-Z0-9+.-]*:')


def text_lines(path):
    """(line number, text) of the lines outside fenced code blocks, code spans blanked."""
    fence = None
    for number, line in enumerate(path.read_text(encoding='utf-8').split('\n'), 1):
        stripped = line.lstrip()
        marker = re.match(r'(`{3,}|~{3,})', stripped)
        if marker:
            if fence is None:
                fence = marker.group(1)[0] * 3
            elif stripped.startswith(fence):
                fence = None
            continue
        if fence is None:
            yield number, line


def slug(heading):
    """the anchor GitHub gives a heading: lower case, punctuation dropped, spaces to '-'"""
    text = re.sub(r'\[([^\]]*)\]\([^)]*\)', r'\1', heading)  # a link's text only
    text = re.sub(r'<[^>]+>', '', text).lower()
    text = ''.join(c for c in text if c.isalnum() or c in ' -_')
    return text.replace(' ', '-')


def anchors(path, cache={}):
    if path not in cache:
        found, seen = set(), {}
        for _, line in text_lines(path):
            found.update(HTML_ANCHOR.findall(line))
            heading = HEADING.match(line)
            if not heading:
                continue
            base = slug(heading.group(2))
            count = seen.get(base, 0)
            seen[base] = count + 1
            found.add(base if count == 0 else f'{base}-{count}')
        cache[path] = found
    return cache[path]


def problems(page, root):
    for number, line in text_lines(page):
        for target in LINK.findall(CODE_SPAN.sub('', line)):
            if SCHEME.match(target) or target.startswith('/'):
                continue
            file_part, _, anchor = target.partition('#')
            where = f'{os.path.relpath(page, root)}:{number}: link {target}'
            linked = (page.parent / file_part).resolve() if file_part else page
            if not linked.exists():
                yield f'{where}: no file {file_part}'
            elif anchor and linked.suffix == '.md' and anchor not in anchors(linked):
                yield f'{where}: no heading gives #{anchor} in {os.path.relpath(linked, root)}'


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent.parent).resolve()
    pages = [root / 'README.md'] + sorted((root / 'docs').glob('*.md'))
    broken = [p for page in pages if page.exists() for p in problems(page, root)]
    for problem in broken:
        print(problem)
    sys.stdout.flush()
    print(f'check_docs_links: {len(pages)} pages, {len(broken)} broken links', file=sys.stderr)
    return 1 if broken else 0


if __name__ == '__main__':
    sys.exit(main())
