"""Every built-in learner's state from Python: `e3d.Learner` saved by
`to_bytes` / pickling and loaded back goes on with the same bytes as the
learner that never stopped."""

import pickle

import pytest

import e3d

SYMBOL_KINDS = ["e3d", "e3d_relax", "count", "smm", "egreedy", "uniform"]


@pytest.mark.parametrize("kind", SYMBOL_KINDS)
def test_a_saved_learner_continues_like_one_never_stopped(kind):
    l = e3d.Learner("two_rooms", kind, alpha=0.2, epsilon=0.3)
    assert l.name == kind and l.kind == kind
    first = e3d.run_session("two_rooms", learner=l, trials=400, seed=1)
    assert first.learner == kind
    saved = l.to_bytes()
    back = e3d.Learner.from_bytes(saved)
    unpickled = pickle.loads(pickle.dumps(l))
    assert back == l and unpickled == l and back.to_bytes() == saved
    runs = [e3d.run_session("two_rooms", learner=x, trials=300, seed=2) for x in (l, back, unpickled)]
    assert runs[0].effects.tolist() == runs[1].effects.tolist() == runs[2].effects.tolist()
    assert l.to_bytes() == back.to_bytes() == unpickled.to_bytes()
    if kind != "uniform":  # the uniform policy learns nothing
        assert l.to_bytes() != saved


def test_a_learner_state_goes_on_where_the_session_left_it():
    # 400 + 300 trials from a state: the second part starts from what the
    # first learned (not from a fresh learner)
    l = e3d.Learner("two_rooms", "count")
    e3d.run_session("two_rooms", learner=l, trials=400, seed=1)
    fresh = e3d.run_session("two_rooms", learner="count", trials=300, seed=2)
    going_on = e3d.run_session("two_rooms", learner=l, trials=300, seed=2)
    assert fresh.effects.tolist() != going_on.effects.tolist()


def test_the_gaussian_e3d_and_uniform_values_save_and_load():
    for kind, saved_kind in [("e3d", "gaussian_e3d"), ("uniform", "uniform_values")]:
        l = e3d.Learner("arm7_continuous", kind)
        assert l.kind == saved_kind and l.name == kind
        e3d.run_session("arm7_continuous", learner=l, trials=40, seed=3)
        back = pickle.loads(pickle.dumps(l))
        a = e3d.run_session("arm7_continuous", learner=l, trials=30, seed=4)
        b = e3d.run_session("arm7_continuous", learner=back, trials=30, seed=4)
        assert a.commands.tolist() == b.commands.tolist()
        assert l.to_bytes() == back.to_bytes()
    # the Gaussian policy moved: its state is not the fresh one
    l = e3d.Learner("arm7_continuous")
    fresh = l.to_bytes()
    e3d.run_session("arm7_continuous", learner=l, trials=40, seed=3)
    assert l.to_bytes() != fresh


def test_e3d_learner_bytes_read_as_a_learner():
    l = e3d.E3dLearner("two_rooms")
    e3d.run_session("two_rooms", learner=l, trials=200, seed=5)
    as_learner = e3d.Learner.from_bytes(l.to_bytes())
    assert as_learner.kind == "e3d"
    a = e3d.run_session("two_rooms", learner=l, trials=200, seed=6)
    b = e3d.run_session("two_rooms", learner=as_learner, trials=200, seed=6)
    assert a.effects.tolist() == b.effects.tolist() and a.q is not None and b.q is not None
    assert l.to_bytes() == as_learner.to_bytes()


def test_bad_states_and_scenes_that_do_not_fit_are_refused():
    l = e3d.Learner("two_rooms", "smm")
    saved = l.to_bytes()
    for broken, msg in [(b"", "not a learner's state"), (saved[:-5], "the bytes end early"),
                        (saved + b"x", "1 bytes after the state"),
                        (saved[:22], "a learner's state cut before its kind")]:
        with pytest.raises(ValueError, match=msg):
            e3d.Learner.from_bytes(broken)
    with pytest.raises(ValueError, match=r"learner: scene `arm7`: the learner's slots have alphabet sizes \[4, 4, 4, 4, 4, 4, 4\] \(0: values\), the scene's \[3, 3, 3, 3, 3, 3, 3\]"):
        e3d.run_session("arm7", learner=l, trials=5)
    with pytest.raises(ValueError, match="the learner's slots have alphabet sizes"):
        e3d.run_session("arm7_continuous", learner=l, trials=5)
    with pytest.raises(ValueError, match="no saved state"):
        e3d.Learner("two_rooms", "archive")
    with pytest.raises(ValueError, match="learner: "):
        e3d.Learner("two_rooms", "nope")
    with pytest.raises(ValueError, match="eta = 2"):
        e3d.Learner("two_rooms", "e3d", eta=2.0)
