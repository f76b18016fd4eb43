import math
import pathlib
import re

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


def small_file(tmp_path, root):
    path = tmp_path / "small.ron"
    path.write_text(SMALL.replace("scenes/", str(root / "scenes") + "/"))
    return path


def test_out_writes_the_clis_files_byte_for_byte(cli, tmp_path, root):
    path = small_file(tmp_path, root)
    cli("sweep", path, "--out", tmp_path / "cli")
    cols = e3d.run_sweep(path, threads=1, out=tmp_path / "py")
    for f in ["results.csv", "summary.csv", "sweep.ron", "version.txt"]:
        assert (tmp_path / "py" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f
    # the journal holds the same rows (in the order sessions finished)
    def rows(d):
        lines = (tmp_path / d / "journal.txt").read_text().splitlines()
        return sorted(line for line in lines if not line.startswith("#"))
    assert rows("py") == rows("cli")
    # the columns returned are the file's
    want = read_csv((tmp_path / "cli" / "results.csv").read_text())
    assert cols["seed"].tolist() == [int(r["seed"]) for r in want]
    assert cols["kl_to_target"].tolist() == [float(r["kl_to_target"]) for r in want]
    # without out: the same values
    again = e3d.run_sweep(path, threads=2)
    assert list(again) == list(cols)
    for k in cols:
        a, b = again[k], cols[k]
        assert (a.tolist() if isinstance(a, np.ndarray) else a) == pytest.approx(
            b.tolist() if isinstance(b, np.ndarray) else b, nan_ok=True), k


def test_out_refuses_a_folder_in_use_as_the_cli_does(cli, tmp_path, root):
    path = small_file(tmp_path, root)
    e3d.run_sweep(path, out=tmp_path / "o")
    with pytest.raises(OSError) as err:
        e3d.run_sweep(path, out=tmp_path / "o")
    r = cli("sweep", path, "--out", tmp_path / "o", check=False)
    assert r.returncode != 0 and r.stderr.strip().splitlines()[-1] == f"error: {err.value}"
    # resuming a complete folder runs nothing and gives the same rows
    before = (tmp_path / "o" / "results.csv").read_bytes()
    cols = e3d.run_sweep(path, out=tmp_path / "o", resume=True)
    assert (tmp_path / "o" / "results.csv").read_bytes() == before
    assert len(cols["scene"]) == 32


def test_a_dict_is_the_same_sweep_as_its_file(tmp_path, root, monkeypatch):
    monkeypatch.chdir(root)
    d = {
        "name": "small",
        "scenes": ["scenes/two_rooms.ron", "scenes/puck_rooms.ron"],
        "learners": ["e3d", "uniform", "egreedy"],
        "use_reward": [False, True],
        "params": {"beta": [1, 100], "eta": 0.01},
        "sessions": 2,
        "trials": 300,
        "seed": 7,
    }
    text = e3d.sweep_text(d)
    assert text.startswith("Sweep(\n") and "learners: [e3d, uniform, egreedy]" in text
    from_dict = e3d.run_sweep(d, threads=2, out=tmp_path / "d")
    (tmp_path / "f.ron").write_text(SMALL)
    e3d.run_sweep(SMALL, threads=2, out=tmp_path / "t")
    assert (tmp_path / "d" / "results.csv").read_bytes() == (tmp_path / "t" / "results.csv").read_bytes()
    assert from_dict["normalized_entropy"].shape == (32,)


def test_dict_ranges_metrics_and_errors(root, monkeypatch):
    monkeypatch.chdir(root)
    d = {
        "scenes": ["two_rooms"],
        "learners": "e3d",  # one value for a list
        "params": {"beta": {"scale": "Log", "from": 1, "to": 100, "steps": 3}},
        "sessions": 1,
        "trials": 50,
        "metrics": ["normalized_entropy", "cumulative_reward_at_20", "cumulative_reward(50)"],
    }
    cols = e3d.run_sweep(d)
    assert cols["beta"].tolist() == [1.0, 10.0, 100.0]
    assert [k for k in cols if k.startswith("cumulative")] == ["cumulative_reward_at_20", "cumulative_reward_at_50"]
    # the library checks the text: its error names the line and column of the text
    with pytest.raises(e3d.SceneError, match=r"^<string>:3:21: unknown variant `nope`"):
        e3d.run_sweep({**d, "learners": ["e3d", "nope"]})
    with pytest.raises(ValueError, match="expected a name"):
        e3d.sweep_text({**d, "learners": ["not a name"]})
    with pytest.raises(ValueError, match="finite"):
        e3d.sweep_text({**d, "params": {"beta": float("inf")}})


def test_columns_are_those_of_docs_analysis(root, monkeypatch):
    # docs/analysis.md lists results.csv's key columns; run_sweep returns them first
    import re

    text = (root / "docs" / "analysis.md").read_text()
    section = text[text.index("## `e3d sweep FILE --out DIR`"):]
    keys = re.search(r"canonical order: `([^`]*)`", section.replace("\n", " ")).group(1)
    keys = [k.strip() for k in keys.split(",")]
    monkeypatch.chdir(root)
    cols = e3d.run_sweep(SMALL, threads=2)
    assert list(cols)[: len(keys)] == keys
    assert list(cols)[len(keys):] == [
        "normalized_entropy", "normalized_entropy_last_1000", "kl_to_target",
        "distinct_effects", "cumulative_reward_at_300", "first_reward_trial",
        "coverage", "trials_to_50_percent", "trials_to_90_percent", "qd_score", "failure"]
    n = len(cols["scene"])
    assert n == 32 and all(len(v) == n for v in cols.values())


def test_dict_keys_are_field_names_and_strings_are_escaped():
    d = {"scenes": ["two_rooms"], "learners": ["e3d"], "trials": 50}
    # a key cannot write fields of its own into the text
    for bad in (
        {"trials: 5, seed": 1},
        {"params": {"beta: 1), alpha: (": 1}},
        {"params": {"beta": {"from: 1, to": 2}}},
        {3: 1},
    ):
        with pytest.raises(ValueError, match="expected a field name"):
            e3d.sweep_text({**d, **bad})
    # quotes, backslashes and control characters of a string are escaped
    text = e3d.sweep_text({**d, "name": 'a"b\\c\n\x1bz'})
    assert '    name: "a\\"b\\\\c\\u{000a}\\u{001b}z",' in text.splitlines()


def test_scenes_and_names_are_strings_or_paths(root):
    d = {"learners": ["e3d"], "trials": 50}
    assert 'scenes: ["x/y.ron"],' in e3d.sweep_text({**d, "scenes": pathlib.Path("x/y.ron")})
    for bad in (3, [2.5], [e3d.Scene.builtin("two_rooms")], [None]):
        with pytest.raises(TypeError, match=r"^scenes: expected a string \(a scene's name or path"):
            e3d.sweep_text({**d, "scenes": bad})
    with pytest.raises(TypeError, match=r"^name: expected a string"):
        e3d.sweep_text({**d, "scenes": ["two_rooms"], "name": 7})


SWEEP_BASE = {"scenes": ["four_rooms"], "learners": ["e3d"], "sessions": 1, "trials": 50}
BASE_TEXT = 'scenes: ["four_rooms"], learners: [e3d], sessions: 1, trials: 50'


@pytest.mark.parametrize("extra, ron", [
    ({"closed_loop": True}, ["closed_loop: true"]),
    ({"closed_loop": np.True_, "gamma": 0.5}, ["closed_loop: true", "gamma: 0.5"]),
    ({"observe": "State"}, ["observe: State"]),
    ({"observe": "state"}, ["observe: State"]),  # as run_episodes spells it
    ({"observe": "start", "commands": np.int64(2)}, ["observe: StartContext", "commands: 2"]),
    ({"observe": "Blind", "commands": 2}, ["observe: Blind", "commands: 2"]),
    ({"use_reward": (np.False_, True)}, ["use_reward: [false, true]"]),
    ({"params": {"beta": (1, 10), "k": np.int64(3), "sigma": np.float32(0.5)}},
     ["params: (beta: [1, 10], k: 3, sigma: 0.5)"]),
    ({"params": {"beta": {"scale": "Log", "from": 1, "to": 100, "steps": np.int64(3)}}},
     ["params: (beta: (scale: Log, from: 1, to: 100, steps: 3))"]),
    ({"observe": None, "gamma": None, "metrics": None, "commands": None}, []),  # None: the default
])
def test_dict_values_are_written_in_their_fields_ron_form(extra, ron, tmp_path):
    # each value in its field's RON form: the same sweep as the file
    text = e3d.sweep_text({**SWEEP_BASE, **extra})
    assert text.splitlines()[5:-1] == [f"    {part}," for part in ron], text
    e3d.run_sweep({**SWEEP_BASE, **extra}, threads=1, out=tmp_path / "d")
    e3d.run_sweep(f"Sweep({BASE_TEXT}, {', '.join(ron)})", threads=1, out=tmp_path / "f")
    assert (tmp_path / "d" / "results.csv").read_bytes() == (tmp_path / "f" / "results.csv").read_bytes()


def test_dict_metrics_of_start_contexts_by_column_name():
    text = e3d.sweep_text({**SWEEP_BASE, "commands": 2, "metrics": [
        "normalized_entropy_context_0", "cumulative_reward_context(0)", "first_reward_trial_context_0",
        "normalized_entropy_last_1000"]})
    assert ("metrics: [normalized_entropy_context(0), cumulative_reward_context(0), "
            "first_reward_trial_context(0), normalized_entropy_last_1000]") in text
    cols = e3d.run_sweep(text)
    assert "normalized_entropy_context_0" in cols and "first_reward_trial_context_0" in cols


def test_dict_values_of_the_wrong_type_name_their_field():
    # an unknown name is the library's to refuse, with the names it knows
    with pytest.raises(e3d.SceneError, match=r"unknown variant `Nope` for `Observe`; expected one of: StartContext, State, Blind"):
        e3d.run_sweep({**SWEEP_BASE, "observe": "Nope"})
    with pytest.raises(e3d.SceneError, match=r"unknown variant `Square`"):
        e3d.run_sweep({**SWEEP_BASE, "params": {"beta": {"scale": "Square", "from": 1, "to": 2, "steps": 2}}})
    # text that is no name cannot write more than a name
    for bad in ("State, closed_loop: true", 3, True):
        with pytest.raises(ValueError, match=r"^observe: expected a name"):
            e3d.sweep_text({**SWEEP_BASE, "observe": bad})
    for field in ("closed_loop",):
        for bad in ("yes", 1, "true"):
            with pytest.raises(TypeError, match=rf"^{field}: expected True or False"):
                e3d.sweep_text({**SWEEP_BASE, field: bad})
    for bad in ([1], ["true"]):
        with pytest.raises(TypeError, match=r"^use_reward: expected True or False"):
            e3d.sweep_text({**SWEEP_BASE, "use_reward": bad})
    # integers: not bools, floats or strings (as run_session and e3d.gym)
    for field in ("sessions", "trials", "seed", "commands"):
        for bad in (True, 2.0, "2", np.float64(2)):
            with pytest.raises(TypeError, match=rf"^{field}: expected an integer"):
                e3d.sweep_text({**SWEEP_BASE, field: bad})
    for params, where in (
        ({"k": 2.0}, "params.k"),
        ({"k": True}, "params.k"),
        ({"beta": {"scale": "Log", "from": 1, "to": 2, "steps": True}}, "params.beta.steps"),
        ({"beta": {"scale": "Log", "from": 1, "to": 2, "steps": 2.9}}, "params.beta.steps"),
    ):
        with pytest.raises(TypeError, match=rf"^{where}: expected an integer"):
            e3d.sweep_text({**SWEEP_BASE, "params": params})
    for params, where in (({"beta": np.True_}, "params.beta"), ({"sigma": "0.1"}, "params.sigma"),
                          ({"beta": ["1"]}, "params.beta")):
        with pytest.raises(TypeError, match=rf"^{where}: expected a number"):
            e3d.sweep_text({**SWEEP_BASE, "params": params})
    with pytest.raises(TypeError, match=r"^gamma: expected a number, found a bool"):
        e3d.sweep_text({**SWEEP_BASE, "gamma": True})
    # the range is the library's to check, named as in a file
    with pytest.raises(e3d.SceneError, match=r"field `seed`: integer is out of bounds"):
        e3d.run_sweep({**SWEEP_BASE, "seed": 2**70})
    # an unknown field in RON form: refused by the library for its name
    text = e3d.sweep_text({**SWEEP_BASE, "frob": {"a": (1, True, None)}})
    assert "    frob: (a: [1, true, None])," in text.splitlines()
    with pytest.raises(e3d.SceneError, match=r"unknown field `frob` in `Sweep`"):
        e3d.run_sweep(text)


@pytest.mark.parametrize("name,axis", [("arm7_damping", "joints.j1.damping"),
                                       ("puck_noise", "noise.actions.Gaussian.sd")])
def test_the_example_sweeps_over_scene_fields_give_the_clis_bytes(name, axis, cli, tmp_path, root):
    # the shipped example, shrunk: 2 sessions of 60 trials per cell
    text = (root / "scenes" / "sweeps" / f"{name}.ron").read_text()
    text = re.sub(r"sessions: \d+", "sessions: 2", text)
    text = re.sub(r"trials: \d+", "trials: 60", text).replace("cumulative_reward(2000)", "cumulative_reward(60)")
    text = text.replace('"../', f'"{root / "scenes"}/')
    path = tmp_path / f"{name}.ron"
    path.write_text(text)
    cli("sweep", path, "--out", tmp_path / "cli")
    cols = e3d.run_sweep(path, threads=2, out=tmp_path / "py")
    for f in ["results.csv", "summary.csv", "sweep.ron", "version.txt"]:
        assert (tmp_path / "py" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f
    header = (tmp_path / "cli" / "results.csv").read_text().splitlines()[0]
    assert f",epsilon,{axis},session,seed," in header
    assert sorted(set(cols[axis].tolist())) == ([0.125, 0.5, 2.0] if name == "arm7_damping" else [0.0, 0.05, 0.2])


def test_axes_from_a_dict_are_columns_and_bad_paths_are_placed():
    d = {"scenes": ["two_rooms"], "learners": ["e3d", "uniform"], "axes": {"command.slots": [5, 7]},
         "sessions": 2, "trials": 100, "seed": 1}
    assert 'axes: {"command.slots": [5, 7]},' in e3d.sweep_text(d)
    cols = e3d.run_sweep(d)
    assert cols["command.slots"].tolist() == [5.0] * 4 + [7.0] * 4
    assert cols["learner"] == ["e3d", "e3d", "uniform", "uniform"] * 2
    # fewer moves, fewer cells reached
    assert cols["distinct_effects"][:4].sum() < cols["distinct_effects"][4:].sum()
    with pytest.raises(e3d.SceneError, match=r"^<string>:\d+:\d+: field `axes`: .*unknown field `joints`, expected one of `rows`"):
        e3d.run_sweep({**d, "axes": {"joints.j1.damping": [1.0]}})
    with pytest.raises(TypeError, match="axes: expected a dict of scene field paths"):
        e3d.run_sweep({**d, "axes": [1.0]})
