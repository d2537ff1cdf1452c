#!/usr/bin/python3
"""cmake/git_commit.cmake, the commit a build records (enact --version, a sweep's manifest),
run as the build runs it on real git folders:

  a repository at a commit            its 40 hex digits (what git rev-parse HEAD says)
  a tracked file changed              the digits and "-dirty"; an untracked file: clean
  a source outside git (a tarball)    "unknown"
  a source folder inside another
  repository (a tarball unpacked
  in one)                             "unknown": that repository's commit is not its own
  run again, nothing changed          the header is not rewritten (nothing rebuilds)

  git_commit_test.py CMAKE SOURCE_ROOT
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

CMAKE, ROOT = sys.argv[1], sys.argv[2]
SCRIPT = os.path.join(ROOT, "cmake", "git_commit.cmake")


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def commit_of(source, out):
    """What the script writes for `source`: the value of ENACT_GIT_COMMIT."""
    subprocess.run([CMAKE, f"-DSOURCE_DIR={source}", f"-DOUT={out}", "-P", SCRIPT], check=True)
    with open(out) as f:
        m = re.search(r'#define ENACT_GIT_COMMIT "([^"]*)"', f.read())
    if not m:
        fail(f"{out} defines no ENACT_GIT_COMMIT")
    return m.group(1)


def git(repo, *args):
    return subprocess.run(["git", "-C", repo, "-c", "user.name=test", "-c", "user.email=test@localhost", *args], check=True,
                          stdout=subprocess.PIPE, text=True).stdout.strip()


def main():
    if shutil.which("git") is None:
        print("SKIP: git is not installed")
        sys.exit(77)
    tmp = tempfile.mkdtemp(prefix="enact_git_commit_")
    try:
        header = os.path.join(tmp, "enact_git_commit.h")
        # outside git
        plain = os.path.join(tmp, "tarball")
        os.makedirs(plain)
        if (c := commit_of(plain, header)) != "unknown":
            fail(f"a source outside git: {c!r}, expected 'unknown'")
        # a repository at a commit, then a tracked file changed, then an untracked file only
        repo = os.path.join(tmp, "repo")
        os.makedirs(repo)
        git(repo, "init", "-q")
        with open(os.path.join(repo, "a.txt"), "w") as f:
            f.write("a\n")
        git(repo, "add", "a.txt")
        git(repo, "commit", "-q", "-m", "one")
        head = git(repo, "rev-parse", "HEAD")
        if (c := commit_of(repo, header)) != head:
            fail(f"a repository at {head}: {c!r}")
        before = os.stat(header).st_mtime_ns
        if commit_of(repo, header) != head or os.stat(header).st_mtime_ns != before:
            fail("run again at the same commit: the header was rewritten (everything including it rebuilds)")
        with open(os.path.join(repo, "a.txt"), "a") as f:
            f.write("changed\n")
        if (c := commit_of(repo, header)) != head + "-dirty":
            fail(f"a tracked file changed: {c!r}, expected {head}-dirty")
        git(repo, "checkout", "-q", "a.txt")
        with open(os.path.join(repo, "new.txt"), "w") as f:
            f.write("untracked\n")
        if (c := commit_of(repo, header)) != head:
            fail(f"an untracked file only: {c!r}, expected {head}")
        # a source unpacked inside another repository
        inside = os.path.join(repo, "unpacked", "enact-0.1.0")
        os.makedirs(inside)
        if (c := commit_of(inside, header)) != "unknown":
            fail(f"a source folder inside another repository: {c!r}, expected 'unknown'")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("git_commit: ok")


if __name__ == "__main__":
    main()
