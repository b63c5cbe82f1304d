"""The README's Python example runs as written (from the repository root)."""

import re

from conftest import ROOT


def test_readme_python_example_runs():
    readme = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", readme, re.S)
    assert blocks, "README.md has a Python example"
    for block in blocks:
        exec(compile(block, "README.md", "exec"), {})
