"""python/examples/quickstart.py runs and reproduces Figure 2's numbers, those
of docs/figures/summary.md (`e3d reproduce`)."""

import re
import subprocess
import sys


def test_quickstart_reproduces_figure_2(root):
    r = subprocess.run([sys.executable, str(root / "python" / "examples" / "quickstart.py")],
                       capture_output=True, text=True, cwd=root, timeout=600)
    assert r.returncode == 0, r.stderr
    summary = (root / "docs" / "figures" / "summary.md").read_text()
    published = {
        "uniform": re.search(r"\| 1 \| uniform policy \| ([^|]+) \|", summary).group(1).strip(),
        "e3d": re.search(r"\| 1 \| E3D \| ([^|]+) \|", summary).group(1).strip(),
    }
    number = r"\d\.\d{3} \+- \d\.\d{3} \[\d\.\d{3}, \d\.\d{3}\]"
    for learner, want in published.items():
        line = next(line for line in r.stdout.splitlines() if line.startswith(f"{learner} "))
        mine, theirs = re.findall(number, line)
        assert mine == theirs == want, line
    assert "its command" in r.stdout and "frames over" in r.stdout
