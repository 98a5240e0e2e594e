"""Print pip constraints pinning every direct dependency of pyproject.toml (and the test
extra) to the lowest version it allows: `pip install -c <(python .ci/lowest.py) -e ".[test]"`
installs the oldest environment a user can get (transitive dependencies resolve as usual)."""

import re
import sys
import tomllib
from pathlib import Path

project = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())["project"]
for requirement in project["dependencies"] + project["optional-dependencies"]["test"]:
    match = re.fullmatch(r"([A-Za-z0-9_.-]+)(?:\[[^\]]*\])?>=([^,;\s]+)", requirement.replace(" ", ""))
    if match is None:
        sys.exit(f"{requirement!r}: every dependency needs a lower bound of the form 'name>=version'")
    print(f"{match.group(1)}=={match.group(2)}")
