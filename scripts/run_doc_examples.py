#!/usr/bin/env python3
"""Run the shell examples of README.md and docs/*.md that are marked runnable.

Usage: scripts/run_doc_examples.py [--list] [--only FILE[:LINE]] [--build DIR | --installed PREFIX] [--root DIR] [--keep] [FILE.md...]

A block is runnable when the line right before its ```sh fence is a marker, an HTML comment
GitHub does not show:

    <!-- runnable -->
    <!-- runnable: timeout=90 beside "enact launch launch/bridge_rt.yaml" replace "--duration 10" "--duration 2" -->

Its settings (shell words):
  timeout=S            the block may take S seconds (default 60); then it is stopped and fails
  replace FROM TO      run the block with every FROM written TO (a shorter duration for CI);
                       FROM must be in the block
  beside COMMAND       COMMAND (enact launch ...) runs in another terminal while the block
                       runs: started first, the block starts once it says its graph is ready
                       ("enact launch: graph NAME ready"), stopped after it as by Ctrl-C; it
                       must then exit 0
  display              the block runs on a display of its own (xvfb-run), for the live viewer
  output               the comment lines right after a command, and a plain ``` block right
                       after this one, are its expected output: each must be a line of the
                       block's output, in order ("..." in one matches any text)

In every runnable block, a command whose comment ends in "(exit N)" must exit with status N.
Each block runs with bash -e -o pipefail in a temporary folder that looks like the top of
the repository (its entries linked, build/ the build folder), the build's nodes/*/
executables first on PATH, a graph registry (ENACT_REGISTRY) and HOME of its own; blocks of
one file share that folder in order (a later block may use an earlier block's recording),
each file starts in a fresh one. A file stops at its first failing block. Without a display
option, DISPLAY is unset (a snapshot renders offscreen). A block running enact-viewer is
skipped when the build has none (ENACT_VIEWER=OFF).

--installed PREFIX runs the blocks as a user of an installed enact does (cmake --install
build --prefix PREFIX): each file's folder is an empty folder of one's own (nothing of the
repository in it), PATH is PREFIX/bin then /usr/bin:/bin, so every file a block names is
found as the installed tool finds it (tests/install/installed_tour.sh).

--list lists every sh block, marked or not, and the count per file; --only FILE runs one
file's blocks, FILE:LINE the blocks of FILE up to the one at LINE (the ones before it make
what it uses). Exits 0 when every block ran as documented, 1 naming each one that did not
(FILE:LINE, the command, its output), 2 for a bad marker or bad arguments. Standard library
only (how to mark a block: docs/building.md, "Examples that run").
"""
import argparse
import dataclasses
import itertools
import os
import pathlib
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
FENCE = re.compile(r'^(\s*)(`{3,}|~{3,})\s*(\S*)')
MARKER = re.compile(r'^\s*<!--\s*runnable(?::(.*?))?\s*-->\s*$')
SHELLS = ('sh', 'bash', 'shell')
EXPECTED_EXIT = re.compile(r'^(?P<command>[^#]*\S)\s+#.*\(exit (?P<status>\d+)\)\s*$')
READY = re.compile(r'^enact launch: graph \S+ ready', re.M)  # what a beside graph says once every node is up
DEFAULT_TIMEOUT_S = 60.0
STOP_GRACE_S = 10.0


class MarkerError(Exception):
    """a marker the runner cannot follow: FILE:LINE: problem, and the fix"""


@dataclasses.dataclass
class Block:
    file: str            # relative to the root
    line: int            # the line of the opening fence
    code: list           # the lines inside the fence
    runnable: bool
    marker: str = ''     # the marker's settings as written
    timeout_s: float = DEFAULT_TIMEOUT_S
    replace: list = dataclasses.field(default_factory=list)  # (FROM, TO)
    beside: str = ''
    display: bool = False
    output: bool = False
    shown: list = dataclasses.field(default_factory=list)  # (line, text) of a plain ``` block right after: its output

    @property
    def where(self):
        return f'{self.file}:{self.line}'

    def covers(self, line):
        return self.line - 1 <= line <= self.line + len(self.code) + 1


def parse_settings(block, text, where):
    """the marker's settings into the block; MarkerError on anything else"""
    try:
        words = shlex.split(text or '')
    except ValueError as e:
        raise MarkerError(f'{where}: the runnable marker: {e}\n  fix: quote each setting\'s words with "..."')
    while words:
        word = words.pop(0)
        if word.startswith('timeout='):
            try:
                block.timeout_s = float(word.split('=', 1)[1])
            except ValueError:
                raise MarkerError(f'{where}: the runnable marker: {word} is not a number of seconds\n  fix: e.g. timeout=90')
        elif word in ('replace', 'beside'):
            needed, usage = (2, 'replace "FROM" "TO"') if word == 'replace' else (1, 'beside "enact launch FILE"')
            if len(words) < needed:
                raise MarkerError(f'{where}: the runnable marker: {word} needs {needed} quoted word(s)\n  fix: {usage}')
            args, words = words[:needed], words[needed:]
            if word == 'replace':
                block.replace.append(tuple(args))
            else:
                block.beside = args[0]
        elif word in ('display', 'output'):
            setattr(block, word, True)
        else:
            raise MarkerError(f'{where}: the runnable marker: unknown setting "{word}"\n'
                              '  fix: timeout=S, replace "FROM" "TO", beside "COMMAND", display or output (scripts/run_doc_examples.py --help)')


def blocks_of(root, relative):
    """every fenced shell block of a markdown file, runnable (marked) or not"""
    lines = (root / relative).read_text(encoding='utf-8').split('\n')
    found, number = [], 0
    while number < len(lines):
        marker = MARKER.match(lines[number])
        opening = FENCE.match(lines[number + 1]) if marker and number + 1 < len(lines) else FENCE.match(lines[number])
        if marker and not (opening and opening.group(3) in SHELLS):
            raise MarkerError(f'{relative}:{number + 1}: a runnable marker must be the line right before a ```sh block\n'
                              '  fix: move it there, or remove it')
        if not opening:
            number += 1
            continue
        start = number + 1 if marker else number
        indent, fence = opening.group(1), opening.group(2)
        end = start + 1
        while end < len(lines) and not lines[end].strip().startswith(fence):
            end += 1
        if opening.group(3) in SHELLS:
            code = [line[len(indent):] if line.startswith(indent) else line for line in lines[start + 1:end]]
            block = Block(relative, start + 1, code, bool(marker))
            if marker:
                block.marker = (marker.group(1) or '').strip()
                parse_settings(block, block.marker, f'{relative}:{number + 1}')
            after = FENCE.match(lines[end + 1]) if end + 1 < len(lines) else None
            if after and not after.group(3):
                shown = itertools.takewhile(lambda line: not line.strip().startswith(after.group(2)), lines[end + 2:])
                block.shown = list(enumerate(shown, end + 3))
            found.append(block)
        number = end + 1
    return found


def script_of(block):
    """the block as bash runs it: replacements made, "(exit N)" commands checked, one line for
    each line of the block (so bash's line numbers are the block's)"""
    text = '\n'.join(block.code)
    for old, new in block.replace:
        if old not in text:
            raise MarkerError(f'{block.where}: replace "{old}": not in the block\n  fix: write what the block says, or remove the replacement')
        text = text.replace(old, new)
    lines = []
    for line in text.split('\n'):
        expected = EXPECTED_EXIT.match(line)
        if expected and not line.lstrip().startswith('#'):
            status = expected.group('status')
            line = (f'set +e; {expected.group("command")}; _status=$?; set -e; [ "$_status" -eq {status} ] || '
                    f'{{ echo "the docs say (exit {status}); it exited $_status" >&2; false; }}')
        lines.append(line)
    return '\n'.join(lines) + '\n'


def expected_output(block):
    """the output a block marked `output` shows: the comment lines right after each command,
    then the plain block right after it"""
    expected, after_command = [], False
    for number, line in enumerate(block.code, block.line + 1):
        stripped = line.strip()
        if not stripped.startswith('#'):
            after_command = bool(stripped)
        elif after_command:
            expected.append((number, stripped[2:] if stripped.startswith('# ') else stripped[1:]))
    return expected + block.shown


def missing_output(expected, output):
    """the first expected (line, text) not found (in order) among the output's lines, else None"""
    lines = [line.rstrip() for line in output.split('\n')]
    at = 0
    for number, want in expected:
        pattern = re.compile('.*'.join(re.escape(part) for part in want.rstrip().split('...')) + r'\Z')
        while at < len(lines) and not pattern.match(lines[at]):
            at += 1
        if at == len(lines):
            return number, want
        at += 1
    return None


def group_alive(pgid):
    """true while a process of the group runs (zombies do not count)"""
    for stat in pathlib.Path('/proc').glob('[0-9]*/stat'):
        try:
            fields = stat.read_text().rsplit(')', 1)[1].split()
        except (OSError, IndexError):
            continue
        if fields[2] == str(pgid) and fields[0] != 'Z':
            return True
    return False


def stop_group(process, first=signal.SIGTERM):
    """`first` to the process's group (SIGINT: Ctrl-C), then SIGTERM, then SIGKILL, until none
    of it runs (a shell's background jobs ignore SIGINT)"""
    for sig in dict.fromkeys((first, signal.SIGTERM, signal.SIGKILL)):
        try:
            os.killpg(process.pid, sig)
        except ProcessLookupError:
            pass
        deadline = time.monotonic() + STOP_GRACE_S
        while time.monotonic() < deadline and (process.poll() is None or group_alive(process.pid)):
            time.sleep(0.05)
        if process.poll() is not None and not group_alive(process.pid):
            return
    process.wait()


class Folder:
    """a file's temporary folder: a view of the repository's top, a HOME, a registry"""

    def __init__(self, root, build, keep, installed=None):
        self.base = pathlib.Path(tempfile.mkdtemp(prefix='enact-docs-'))
        self.keep = keep
        self.top = self.base / 'top'
        self.top.mkdir()
        for name in ('home', 'registry'):
            (self.base / name).mkdir()
        if installed:
            # a folder of one's own, the installed tool only
            self.viewer = installed / 'bin' / 'enact-viewer'
            path = [str(installed / 'bin'), '/usr/bin', '/bin']
        else:
            for entry in root.iterdir():
                if entry.name not in ('.git', 'build'):
                    (self.top / entry.name).symlink_to(entry)
            (self.top / 'build').symlink_to(build)
            self.viewer = build / 'nodes/enact-viewer/enact-viewer'
            path = sorted(str(d) for d in (build / 'nodes').glob('*') if d.is_dir()) + [os.environ.get('PATH', '')]
        self.env = dict(os.environ, HOME=str(self.base / 'home'), ENACT_REGISTRY=str(self.base / 'registry'), PATH=os.pathsep.join(path))
        for name in ('DISPLAY', 'WAYLAND_DISPLAY', 'SDL_VIDEODRIVER'):
            self.env.pop(name, None)

    def close(self):
        if self.keep:
            print(f'kept {self.base}')
        else:
            shutil.rmtree(self.base, ignore_errors=True)


def start(command, folder, block, log):
    """a process group of its own in the folder, its output into the file log"""
    env = dict(folder.env, ENACT_TEST_NAME=f'docs example {block.where}')
    with open(log, 'wb') as out:
        return subprocess.Popen(command, cwd=folder.top, env=env, stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                start_new_session=True)


def read_log(log):
    return log.read_bytes().decode('utf-8', 'replace')


def start_beside(block, log, folder):
    """the block's other terminal, once its graph is ready; (process, None) or (None, the failure)"""
    process = start(['bash', '-c', block.beside], folder, block, log)
    deadline = time.monotonic() + block.timeout_s
    while not READY.search(read_log(log)):
        if process.poll() is not None or time.monotonic() > deadline:
            stop_group(process)
            return None, f'{block.where}: beside "{block.beside}": its graph did not say it was ready (exit {process.returncode})\n{read_log(log)}'
        time.sleep(0.05)
    return process, None


def run_block(block, folder):
    """None when the block ran as documented, else what went wrong"""
    if 'enact-viewer' in '\n'.join(block.code) and not folder.viewer.exists():
        print(f'{block.where}: skipped: this build has no enact-viewer (ENACT_VIEWER=OFF)')
        return None
    files = {kind: folder.base / f'block-{block.line}.{kind}' for kind in ('sh', 'lines', 'log', 'beside')}
    files['sh'].write_text(script_of(block))
    # the shell writes the line of each command it starts (not its subshells') to the .lines file
    shell = ['bash', '-e', '-o', 'pipefail', '-c',
             '_lines=$2; set -T; trap \'if [ "$BASHPID" = "$$" ]; then echo "$LINENO" >>"$_lines"; fi\' DEBUG; source "$1"',
             'bash', str(files['sh']), str(files['lines'])]
    if block.display and not shutil.which('xvfb-run'):
        return f'{block.where}: the block needs a display (xvfb-run), and there is none\n  fix: apt-get install xvfb\n'
    if block.display:
        shell = ['xvfb-run', '-a', '-s', '-screen 0 1280x800x24 -nolisten tcp'] + shell
    beside, failure = start_beside(block, files['beside'], folder) if block.beside else (None, None)
    if failure:
        return failure
    process = start(shell, folder, block, files['log'])
    try:
        status = process.wait(timeout=block.timeout_s)
        problem = None if status == 0 else f'exited {status}'
    except subprocess.TimeoutExpired:
        problem = f'still ran after timeout={block.timeout_s:g} s'
    stop_group(process)
    output = read_log(files['log'])
    if problem is None and block.output:
        missing = missing_output(expected_output(block), output)
        problem = None if missing is None else f'printed no line "{missing[1]}" (its output, as {block.file}:{missing[0]} shows it)'
    if beside:
        stop_group(beside, signal.SIGINT)
        if beside.returncode != 0:
            problem = problem or f'ran, but beside "{block.beside}" exited {beside.returncode} when stopped'
            output += f'\n  (beside "{block.beside}" printed:)\n{read_log(files["beside"])}'
    return None if problem is None else describe(block, problem, files['lines'], output)


def describe(block, problem, trace, output):
    """FILE:LINE of the command, the block as run, its output"""
    numbers = trace.read_text().split() if trace.exists() else []
    line = int(numbers[-1]) if numbers else 1
    command = block.code[line - 1].strip() if 0 < line <= len(block.code) else ''
    as_run = ''.join(f'    {text}\n' for text in script_of(block).rstrip('\n').split('\n'))
    said = ''.join(f'    {text}\n' for text in output.rstrip('\n').split('\n'))
    return (f'{block.file}:{block.line + line}: the example at {block.where} {problem}: {command}\n'
            f'  the block as run (bash -e -o pipefail):\n{as_run}  its output:\n{said}')


def run_file(blocks, root, build, keep, installed=None):
    """runs a file's blocks in order in one folder; the number that failed (0 or 1)"""
    folder = Folder(root, build, keep, installed)
    try:
        for block in blocks:
            print(f'{block.where}: running', flush=True)
            started = time.monotonic()
            failure = run_block(block, folder)
            if failure:
                print(failure, end='')
                later = len(blocks) - blocks.index(block) - 1
                if later:
                    print(f'{block.file}: its {later} later block(s) not run')
                return 1
            print(f'{block.where}: ok ({time.monotonic() - started:.1f} s)', flush=True)
        return 0
    finally:
        folder.close()


def list_blocks(files):
    """each sh block: FILE:LINE, runnable (with its settings) or not, its first line; the counts"""
    counts = [0, 0]
    for relative, blocks in files.items():
        for block in blocks:
            state = f'runnable {block.marker}'.rstrip() if block.runnable else 'not marked'
            print(f'{block.where}: {state}   {block.code[0].strip() if block.code else ""}')
        runs = sum(b.runnable for b in blocks)
        if blocks:
            print(f'{relative}: {runs} runnable, {len(blocks) - runs} not marked')
        counts = [counts[0] + runs, counts[1] + len(blocks) - runs]
    print(f'all: {counts[0]} runnable, {counts[1]} not marked')


def load(root, names):
    """each file's sh blocks; MarkerError for a marker the runner cannot follow, before anything runs"""
    files = {name: blocks_of(root, name) for name in names}
    for block in (b for blocks in files.values() for b in blocks if b.runnable):
        script_of(block)  # a replacement that is not in the block
    return files


def up_to(blocks, relative, line):
    """the runnable blocks of a file up to the one covering line (FILE:LINE)"""
    last = next((b for b in blocks if line.isdigit() and b.covers(int(line))), None)
    if last is None or not last.runnable:
        raise MarkerError(f'{relative}:{line}: no runnable block there (--list shows them)')
    return blocks[:blocks.index(last) + 1]


def main():
    head, usage, rest = __doc__.split('\n', 3)[0], __doc__.split('\n')[2][7:], __doc__.split('\n', 3)[3]
    parser = argparse.ArgumentParser(description=head, usage=usage, epilog=rest, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('files', nargs='*', help='markdown files (default: README.md and docs/*.md)')
    parser.add_argument('--root', default=str(ROOT), help='the repository (default: this script\'s ..)')
    parser.add_argument('--build', default=os.environ.get('ENACT_BUILD_DIR'), help='the build folder (default $ENACT_BUILD_DIR, else ROOT/build)')
    parser.add_argument('--installed', metavar='PREFIX', help='run the blocks with the enact installed in PREFIX, from a folder of their own')
    parser.add_argument('--list', action='store_true', help='list the sh blocks, runnable or not, and the counts')
    parser.add_argument('--only', metavar='FILE[:LINE]', help='one file, or its blocks up to the one at LINE')
    parser.add_argument('--keep', action='store_true', help='keep the temporary folders (their path is printed)')
    args = parser.parse_args()
    root = pathlib.Path(args.root).resolve()
    build = pathlib.Path(args.build or root / 'build').resolve()
    names = args.files or ['README.md'] + sorted(str(p.relative_to(root)) for p in (root / 'docs').glob('*.md'))
    only_file, _, only_line = (args.only or '').partition(':')
    if only_file:
        names = [only_file]
    try:
        files = load(root, names)
        if only_line:
            files = {only_file: up_to(files[only_file], only_file, only_line)}
    except (MarkerError, OSError) as e:
        print(e, file=sys.stderr)
        return 2
    if args.list:
        list_blocks(files)
        return 0
    installed = pathlib.Path(args.installed).resolve() if args.installed else None
    if installed and not (installed / 'bin' / 'enact').is_file():
        print(f'{installed}: no installed enact (bin/enact)\n  fix: cmake --install build --prefix {installed}', file=sys.stderr)
        return 2
    if not installed and not build.is_dir():
        print(f'{build}: no build folder\n  fix: build first (scripts/build.sh), or give --build DIR', file=sys.stderr)
        return 2
    failed = sum(run_file([b for b in blocks if b.runnable], root, build, args.keep, installed) for blocks in files.values() if any(b.runnable for b in blocks))
    print(f'{failed} file(s) with a failing example' if failed else 'every runnable example ran as documented')
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
