"""The repository stands alone: no tracked file names a path outside it."""

import re
import subprocess

from conftest import REPO


def test_no_file_reaches_outside_the_repo():
    files = subprocess.run(["git", "ls-files"], cwd=REPO, capture_output=True, text=True, check=True).stdout.split()
    outside = re.compile(r"\.\./shared|/work/|(?<![\w.])/home/|/Users/")
    hits = []
    for name in files:
        path = REPO / name
        if path.suffix in {".gz", ".igs", ".png", ".json"} or not path.is_file():
            continue
        for k, line in enumerate(path.read_text(errors="ignore").splitlines(), 1):
            if outside.search(line) and name != "tests/test_repo.py":
                hits.append(f"{name}:{k}: {line.strip()}")
    assert not hits, "\n".join(hits)
