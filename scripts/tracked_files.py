#!/usr/bin/env python3
"""The files of the source tree, for the checks that read it (imported, not run).

    from tracked_files import tracked_files
    tracked_files(root)  # sorted paths relative to root, '/'-separated

git's list of tracked files when `root` is a git checkout (a fresh file is not checked until it
is added); else a walk of the tree that skips folders starting with '.', 'build' or 'out'.
Used by scripts/decisions_index.py, tests/docs/source_limits.py and
tests/docs/no_dangling_refs.py. Python 3 standard library only.
"""

import os
import subprocess


def tracked_files(root):
    """Sorted paths of the tree's files relative to `root`: git's list, else a walk."""
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z"], check=True,
                             capture_output=True).stdout.decode("utf-8", "replace")
        return sorted(f for f in out.split("\0") if f)
    except (OSError, subprocess.CalledProcessError):
        files = []
        for d, dirs, fs in os.walk(root):
            dirs[:] = sorted(x for x in dirs if not x.startswith((".", "build", "out")))
            rel = os.path.relpath(d, root)
            files += [os.path.normpath(os.path.join(rel, x)).replace(os.sep, "/") for x in fs]
        return sorted(files)
