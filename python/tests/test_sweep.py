import math

import numpy as np
import pytest

import e3d

from conftest import read_csv

SMALL = """Sweep(
    name: "small",
    scenes: ["scenes/two_rooms.ron", "scenes/puck_rooms.ron"],
    learners: [e3d, uniform, egreedy],
    use_reward: [false, true],
    params: (beta: [1, 100], eta: 0.01),
    sessions: 2,
    trials: 300,
    seed: 7,
)
"""


def typed(name, text):
    if name in ("scene", "learner", "failure"):
        return text
    if name == "use_reward":
        return text == "true"
    if name in ("session", "seed"):
        return int(text)
    return float(text) if text != "" else math.nan


def same(a, b):
    if isinstance(a, float) and math.isnan(a):
        return isinstance(b, float) and math.isnan(b)
    return a == b


def test_run_sweep_equals_the_cli(cli, tmp_path, root, monkeypatch):
    path = tmp_path / "small.ron"
    # scene paths relative to the sweep's folder
    path.write_text(SMALL.replace("scenes/", str(root / "scenes") + "/"))
    cli("sweep", path, "--out", tmp_path / "out")
    rows = read_csv((tmp_path / "out" / "results.csv").read_text())
    cols = e3d.run_sweep(path, threads=2)
    header = (tmp_path / "out" / "results.csv").read_text().splitlines()[0].split(",")
    assert list(cols) == header
    n = len(rows)
    # per scene: e3d 2 rewards x 2 betas, uniform and egreedy 2 rewards (beta unused); 2 sessions
    assert n == 2 * (4 + 2 + 2) * 2
    for name in header:
        got = cols[name]
        assert len(got) == n
        want = [typed(name, r[name]) for r in rows]
        values = got.tolist() if isinstance(got, np.ndarray) else got
        assert all(same(w, g) for w, g in zip(want, values)), name
    assert cols["seed"].dtype == np.uint64
    assert cols["use_reward"].dtype == np.bool_
    # the same text, scene paths relative to the current folder, and threads
    monkeypatch.chdir(root)
    again = e3d.run_sweep(SMALL, threads=1)
    assert again["normalized_entropy"].tolist() == cols["normalized_entropy"].tolist()


def test_sweep_errors_name_file_line_and_column(tmp_path, cli):
    bad = tmp_path / "bad.ron"
    bad.write_text('Sweep(\n    scenes: ["two_rooms"],\n    learners: [e3d, nope],\n    sessions: 1,\n    trials: 10,\n)\n')
    with pytest.raises(e3d.SceneError) as err:
        e3d.run_sweep(bad)
    assert str(err.value).startswith(f"{bad}:3:")
    r = cli("sweep", bad, "--out", tmp_path / "o", check=False)
    assert r.stderr.strip().splitlines()[-1] == f"error: {err.value}"
    with pytest.raises(e3d.SceneError, match="^<string>"):
        e3d.run_sweep("Sweep(scenes: [])")
