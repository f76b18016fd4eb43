"""E3D's insides from Python: the target p*, the final policy, and the
summary.json fields with the CLI's names."""

import json

import numpy as np
import pytest

import e3d


def test_summary_fields_are_the_clis(cli, tmp_path):
    out = tmp_path / "run"
    cli("run", "two_rooms", "--trials", 2000, "--seed", 5, "--out", out)
    summary = json.loads((out / "summary.json").read_text())
    rec = e3d.run_session("two_rooms", trials=2000, seed=5)
    for k, v in rec.metrics.items():
        assert summary[k] == v, k
    assert set(rec.metrics) >= {"reachable_effects", "normalized_entropy_reachable"}
    assert rec.effect_counts.tolist() == summary["effect_counts"]
    assert rec.policy_effect_distribution.tolist() == summary["policy_effect_distribution"]
    assert abs(rec.policy_effect_distribution.sum() - 1.0) < 1e-9


def test_final_policy_is_each_slots_softmax():
    rec = e3d.run_session("two_rooms", trials=3000, seed=2, beta=5.0)
    pol = rec.final_policy
    assert len(pol) == 7 and all(p.shape == (4,) for p in pol)
    assert all(abs(p.sum() - 1.0) < 1e-12 for p in pol)
    # learnt: not uniform any more
    assert max(float(np.abs(p - 0.25).max()) for p in pol) > 0.05
    assert e3d.run_session("two_rooms", learner="uniform", trials=10).final_policy[0].tolist() == [0.25] * 4
    batch = e3d.run_sessions("two_rooms", trials=3000, seeds=[2], beta=5.0)
    assert [p.tolist() for p in batch[0].final_policy] == [p.tolist() for p in pol]


def test_target_as_array_or_cells():
    scene = e3d.Scene.builtin("two_rooms")
    rows, cols, _, _ = scene.effect_grid
    w = np.zeros(scene.num_effects)
    w[cols - 1] = 3.0
    w[0] = 1.0
    a = e3d.run_session(scene, trials=1500, seed=1, target=w)
    b = e3d.run_session(scene, trials=1500, seed=1, target={(0, cols - 1): 3.0, 0: 1.0})
    u = e3d.run_session(scene, trials=1500, seed=1)
    assert a.effects.tolist() == b.effects.tolist()
    assert a.effects.tolist() != u.effects.tolist()
    # the metrics' KL is against the target given
    assert a.metrics["kl_to_target"] != u.metrics["kl_to_target"]
    # E3D drives towards p*: the two weighted cells get most trials
    late = a.effects[500:]
    assert np.isin(late, [0, cols - 1]).mean() > np.isin(u.effects[500:], [0, cols - 1]).mean()
    with pytest.raises(ValueError, match=r"target: the target has 3 weights"):
        e3d.run_session(scene, trials=10, target=[1, 2, 3])
    with pytest.raises(ValueError, match=r"target: key \(9, 9\) is not an effect"):
        e3d.run_session(scene, trials=10, target={(9, 9): 1.0})
    with pytest.raises(ValueError, match=r"target: "):
        e3d.run_session(scene, trials=10, target=np.zeros(scene.num_effects))


def test_q_and_effect_model_of_e3d():
    beta, eta = 5.0, 0.01
    rec = e3d.run_session("two_rooms", trials=2000, seed=7, beta=beta, eta=eta)
    assert len(rec.q) == 7 and all(q.shape == (4,) and q.dtype == np.float64 for q in rec.q)
    # the policy is softmax(beta Q), slot by slot
    for q, p in zip(rec.q, rec.final_policy):
        z = np.exp(beta * (q - q.max()))
        assert np.allclose(z / z.sum(), p, rtol=0, atol=1e-12)
    # the effect model is the running histogram p <- (1 - eta) p + eta onehot(e)
    n = e3d.Scene.builtin("two_rooms").num_effects
    p = np.full(n, 1.0 / n)
    for e in rec.effects:
        p *= 1 - eta
        p[e] += eta
    assert rec.effect_model.shape == (n,)
    assert np.allclose(rec.effect_model, p, rtol=0, atol=1e-9)
    assert e3d.run_session("two_rooms", learner="uniform", trials=10).q is None
    assert e3d.run_sessions("two_rooms", trials=10, sessions=1)[0].q is None
