#!/usr/bin/python3
"""scripts/run_doc_examples.py catches a broken example: a renamed option of the real enact
(the fixture renamed_option.md), a failing command, a documented exit status or output that
no longer holds, a block past its timeout, a stale marker; and it runs what is right: blocks
of one file in order in one folder, each file fresh, the build's executables first on PATH,
a graph beside a block. ENACT_BUILD_DIR: the build (for the fixture's enact)."""
import os
import pathlib
import subprocess
import sys
import tempfile
import textwrap
import unittest

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
RUNNER = ROOT / 'scripts' / 'run_doc_examples.py'


# a page whose second block reads what its first one wrote
RECORD_THEN_READ = """\
    <!-- runnable -->
    ```sh
    echo recorded > run.txt
    ```

    <!-- runnable -->
    ```sh
    grep -x recorded run.txt
    test "$(readlink build)" = "$BUILD"
    ```
    """


def run(*args, root=None, build=None):
    """the runner's exit status and its whole output"""
    command = [sys.executable, str(RUNNER), *args]
    command += ['--root', str(root)] if root else []
    command += ['--build', str(build)] if build else []
    done = subprocess.run(command, capture_output=True, text=True, timeout=120)
    return done.returncode, done.stdout + done.stderr


class Pages(unittest.TestCase):
    """markdown pages in a temporary repository, and a build whose nodes/tool/ holds `tool`"""

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory(prefix='enact-docs-test-')
        self.root = pathlib.Path(self.dir.name) / 'repo'
        self.build = pathlib.Path(self.dir.name) / 'build'
        (self.root / 'docs').mkdir(parents=True)
        tool = self.build / 'nodes' / 'tool' / 'tool'
        tool.parent.mkdir(parents=True)
        tool.write_text('#!/bin/sh\necho "tool from the build"\n')
        tool.chmod(0o755)

    def tearDown(self):
        self.dir.cleanup()

    def page(self, name, text):
        (self.root / name).write_text(textwrap.dedent(text))
        return name

    def run_pages(self, *names):
        return run(*names, root=self.root, build=self.build)


class CatchesBrokenExamples(Pages):
    def test_a_renamed_option_of_enact_fails_naming_the_file_line_command_and_output(self):
        build = os.environ.get('ENACT_BUILD_DIR', str(ROOT / 'build'))
        status, out = run('tests/docs/renamed_option.md', build=build)
        self.assertEqual(status, 1, out)
        self.assertIn('tests/docs/renamed_option.md:9: ', out)
        self.assertIn('enact launch launch/bridge_rt.yaml --durration 1', out)
        self.assertIn('unknown option --durration', out)  # enact's own message, from the block's output
        self.assertNotIn('never reached\n', out.split('its output:')[1])

    def test_a_failing_command_stops_its_file_and_names_its_line(self):
        self.page('a.md', """\
            text

            <!-- runnable -->
            ```sh
            echo one
            cat no-such-file
            echo two
            ```

            <!-- runnable -->
            ```sh
            echo later
            ```
            """)
        status, out = self.run_pages('a.md')
        self.assertEqual(status, 1, out)
        self.assertIn('a.md:6: the example at a.md:4 exited 1: cat no-such-file', out)
        self.assertIn('a.md: its 1 later block(s) not run', out)
        self.assertNotIn('a.md:11: running', out)

    def test_a_documented_exit_status_must_hold(self):
        self.page('a.md', """\
            <!-- runnable -->
            ```sh
            false                  # refused (exit 1)
            sh -c 'exit 3'         # (exit 3)
            ```
            """)
        self.page('b.md', """\
            <!-- runnable -->
            ```sh
            true                   # refused (exit 1)
            ```
            """)
        self.assertEqual(self.run_pages('a.md')[0], 0)
        status, out = self.run_pages('b.md')
        self.assertEqual(status, 1, out)
        self.assertIn('b.md:3: ', out)
        self.assertIn('the docs say (exit 1); it exited 0', out)

    def test_the_output_a_block_shows_must_be_printed(self):
        shown = """\
            <!-- runnable: output -->
            ```sh
            printf 'seq 81234 applied\\nfix: %s\\n' "$WORD"
            # seq ... applied
            ```
            ```
            fix: this
            ```
            """
        self.page('right.md', shown.replace('$WORD', 'this'))
        self.page('wrong.md', shown.replace('$WORD', 'that'))
        self.assertEqual(self.run_pages('right.md')[0], 0)
        status, out = self.run_pages('wrong.md')
        self.assertEqual(status, 1, out)
        self.assertIn('printed no line "fix: this" (its output, as wrong.md:7 shows it)', out)

    def test_a_block_past_its_timeout_fails_naming_the_command_that_ran(self):
        self.page('a.md', """\
            <!-- runnable: timeout=1 -->
            ```sh
            echo started
            sleep 30
            ```
            """)
        status, out = self.run_pages('a.md')
        self.assertEqual(status, 1, out)
        self.assertIn('a.md:4: the example at a.md:2 still ran after timeout=1 s: sleep 30', out)

    def test_a_stale_or_misplaced_marker_is_refused_before_anything_runs(self):
        self.page('stale.md', """\
            <!-- runnable: replace "--duration 60" "--duration 2" -->
            ```sh
            touch ran
            tool --seconds 60
            ```
            """)
        self.page('misplaced.md', """\
            <!-- runnable -->

            ```sh
            touch ran
            ```
            """)
        self.page('unknown.md', """\
            <!-- runnable: timout=3 -->
            ```sh
            touch ran
            ```
            """)
        for name, said in (('stale.md', 'stale.md:2: replace "--duration 60": not in the block'),
                           ('misplaced.md', 'misplaced.md:1: a runnable marker must be the line right before a ```sh block'),
                           ('unknown.md', 'unknown.md:1: the runnable marker: unknown setting "timout=3"')):
            status, out = self.run_pages(name)
            self.assertEqual(status, 2, out)
            self.assertIn(said, out)
            self.assertIn('fix: ', out)
            self.assertNotIn('running', out)


class RunsWhatIsRight(Pages):
    def test_blocks_share_their_file_s_folder_in_order_and_each_file_starts_fresh(self):
        self.page('a.md', RECORD_THEN_READ.replace('$BUILD', str(self.build)))
        self.page('b.md', """\
            <!-- runnable -->
            ```sh
            test ! -e run.txt
            test -e a.md               # the repository's entries are there
            ```
            """)
        status, out = self.run_pages('a.md', 'b.md')
        self.assertEqual(status, 0, out)
        self.assertEqual(out.count(': ok ('), 3, out)
        self.assertFalse((self.root / 'run.txt').exists())

    def test_the_build_s_executables_are_first_on_path(self):
        self.page('a.md', """\
            <!-- runnable -->
            ```sh
            tool | grep -x "tool from the build"
            ```
            """)
        status, out = self.run_pages('a.md')
        self.assertEqual(status, 0, out)

    def test_a_replacement_is_what_runs(self):
        self.page('a.md', """\
            <!-- runnable: replace "sleep 600" "sleep 0" timeout=20 -->
            ```sh
            sleep 600 && echo "slept"
            ```
            """)
        status, out = self.run_pages('a.md')
        self.assertEqual(status, 0, out)

    def test_beside_runs_a_graph_while_the_block_runs_and_stops_it_as_ctrl_c(self):
        # a stand-in for enact launch: says its graph is ready once up, answers Ctrl-C by writing "stopped"
        graph = ('trap "echo stopped > stopped.txt; exit 0" INT; sleep 0.5; echo up > up.txt; '
                 'echo "enact launch: graph g ready; observers attach at tcp://127.0.0.1:1" >&2; while true; do sleep 0.1; done')
        self.page('a.md', f"""\
            <!-- runnable: beside '{graph}' -->
            ```sh
            grep -x up up.txt
            test ! -e stopped.txt
            ```

            <!-- runnable -->
            ```sh
            grep -x stopped stopped.txt
            ```
            """)
        status, out = self.run_pages('a.md')
        self.assertEqual(status, 0, out)

    def test_beside_that_fails_when_stopped_fails_the_block(self):
        graph = 'trap "exit 3" INT; echo "enact launch: graph g ready" >&2; while true; do sleep 0.1; done'
        self.page('a.md', f"""\
            <!-- runnable: beside '{graph}' -->
            ```sh
            true
            ```
            """)
        status, out = self.run_pages('a.md')
        self.assertEqual(status, 1, out)
        self.assertIn('exited 3 when stopped', out)

    def test_list_counts_runnable_and_unmarked_blocks_per_file(self):
        self.page('a.md', """\
            <!-- runnable: timeout=5 -->
            ```sh
            echo one
            ```

            ```sh
            sudo reboot
            ```

            ```yaml
            not: shell
            ```
            """)
        status, out = run('--list', 'a.md', root=self.root, build=self.build)
        self.assertEqual(status, 0, out)
        self.assertIn('a.md:2: runnable timeout=5   echo one', out)
        self.assertIn('a.md:6: not marked   sudo reboot', out)
        self.assertIn('a.md: 1 runnable, 1 not marked', out)

    def test_only_runs_a_block_after_the_ones_before_it(self):
        self.page('a.md', RECORD_THEN_READ.replace('$BUILD', str(self.build)) + """
    <!-- runnable -->
    ```sh
    false
    ```
    """)
        status, out = run('--only', 'a.md:9', root=self.root, build=self.build)
        self.assertEqual(status, 0, out)
        self.assertIn('a.md:7: ok', out)
        self.assertNotIn('a.md:13', out)


if __name__ == '__main__':
    unittest.main()
