#!/usr/bin/python3
"""Check that docs/architecture.md is true to the files git tracks.

Usage: scripts/check_architecture.py [ROOT]   (ROOT: the repository, default this script's ..)

Two ways it can go wrong, both reported as FILE:LINE: problem:
- a path the page names in a code span (`core/node/sim.cpp`, `core/graph`, `nodes/enact-rt/`)
  that git does not track, as a file or as a folder holding tracked files;
- a folder of the code (core/X, nodes/X: every folder one level down that holds a tracked
  file) that the page never names: a new library or executable left off the map.
Exits 1 when anything is wrong, 0 otherwise, 77 (skipped) outside a git checkout. Standard library only.
"""
import pathlib
import re
import subprocess
import sys

PAGE = 'docs/architecture.md'
MAPPED = ('core', 'nodes')  # the folders whose every sub-folder the page must name
PATH = re.compile(r'^(?:core|nodes|msgs|tests|scripts|launch|docs)(?:/[\w.+-]+)*/?$')
CODE_SPAN = re.compile(r'`([^`]+)`')


def tracked(root):
    out = subprocess.run(['git', '-C', str(root), 'ls-files'], check=True, capture_output=True, text=True).stdout
    files = set(out.split('\n')) - {''}
    folders = set()
    for f in files:
        parts = f.split('/')
        for i in range(1, len(parts)):
            folders.add('/'.join(parts[:i]))
    return files, folders


def named_paths(page):
    """(line, path) for every code span of the page that is a path of the repository."""
    for number, line in enumerate(page.read_text(encoding='utf-8').split('\n'), 1):
        for span in CODE_SPAN.findall(line):
            for word in span.replace(',', ' ').split():
                if PATH.match(word):
                    yield number, word.rstrip('/')


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    try:
        files, folders = tracked(root)
    except (OSError, subprocess.CalledProcessError) as e:
        print(f'skipped: {root} is not a git checkout ({e}); the check reads git ls-files')
        return 77
    page = root / PAGE
    problems = []
    named = set()
    for number, path in named_paths(page):
        named.add(path)
        if path not in files and path not in folders:
            problems.append(f'{PAGE}:{number}: `{path}` is not in the repository (git ls-files)\n  fix: correct the path, or remove it from the page')
    for top in MAPPED:
        for folder in sorted(f for f in folders if f.startswith(top + '/') and f.count('/') == 1):
            if not any(n == folder or n.startswith(folder + '/') for n in named):
                problems.append(f'{PAGE}:1: the folder {folder} is not on the map\n  fix: name `{folder}` in the layer table (what it holds, what it depends on)')
    for p in problems:
        print(p)
    if problems:
        print(f'{len(problems)} problem(s): docs/architecture.md does not match the code')
        return 1
    print(f'docs/architecture.md: {len(named)} paths named, all tracked; every folder of {", ".join(MAPPED)} on the map')
    return 0


if __name__ == '__main__':
    sys.exit(main())
