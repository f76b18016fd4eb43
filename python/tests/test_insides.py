"""E3D's insides from Python: the target p*, the final policy, and the
summary.json fields with the CLI's names."""

import json
import pickle

import numpy as np
import pytest

import e3d


def test_summary_fields_are_the_clis(cli, tmp_path):
    out = tmp_path / "run"
    cli("run", "two_rooms", "--trials", 2000, "--seed", 5, "--out", out)
    summary = json.loads((out / "summary.json").read_text())
    rec = e3d.run_session("two_rooms", trials=2000, seed=5)
    # a metric summary.json leaves out is None (two_rooms: no qd_score, every command 7 moves)
    for k, v in rec.metrics.items():
        assert summary.get(k) == v, k
    assert rec.metrics["qd_score"] is None and "qd_score" not in summary
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
    # run_sessions keeps them too: each session's record is run_session's
    lockstep = e3d.run_sessions("two_rooms", trials=10, sessions=1)[0]
    alone = e3d.run_session("two_rooms", trials=10, seed=0)
    assert [q.tolist() for q in lockstep.q] == [q.tolist() for q in alone.q]
    assert lockstep.effect_model.tolist() == alone.effect_model.tolist()


def test_e3d_learner_state_reads_and_writes():
    l = e3d.E3dLearner("two_rooms", beta=5.0)
    assert l.alphabet_sizes == [4] * 7 and l.num_effects == 18 and l.beta == 5.0
    assert [q.tolist() for q in l.q] == [[0.0] * 4] * 7
    assert l.policy[3].tolist() == [0.25] * 4
    # a session from the learner is the built-in E3D's, and leaves the learner where it ends
    rec = e3d.run_session("two_rooms", learner=l, trials=2000, seed=7)
    ref = e3d.run_session("two_rooms", trials=2000, seed=7, beta=5.0)
    assert rec.effects.tolist() == ref.effects.tolist()
    assert [q.tolist() for q in l.q] == [q.tolist() for q in ref.q]
    assert l.effect_model.tolist() == ref.effect_model.tolist()
    # write Q: the policy is its softmax
    l.set_q(0, [1.0, 0.0, 0.0, 0.0])
    z = np.exp(5.0 * np.array([1.0, 0.0, 0.0, 0.0]))
    assert np.allclose(l.policy[0], z / z.sum(), rtol=0, atol=1e-15)
    l.set_policy(1, [0.7, 0.1, 0.1, 0.1])
    assert np.allclose(l.policy[1], [0.7, 0.1, 0.1, 0.1], rtol=0, atol=1e-12)
    l.q = [[0.0] * 4] * 7
    assert l.policy[0].tolist() == [0.25] * 4
    p = np.zeros(18)
    p[4] = 1.0
    l.effect_model = p
    assert l.effect_model.tolist() == p.tolist()
    # a written policy drives the session: slot 0 always symbol 2
    l.set_policy(0, [1e-12, 1e-12, 1 - 2e-12 - 1e-12, 1e-12])
    rec = e3d.run_session("two_rooms", learner=l, trials=50, seed=1, use_reward=False)
    assert (rec.commands[:, 0] == 2).mean() > 0.95
    with pytest.raises(ValueError, match=r"Q of slot 0: 3 values given, the slot has 4 symbols"):
        l.set_q(0, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"slot 9: the learner has 7 slots"):
        l.set_q(9, [0.0] * 4)
    with pytest.raises(ValueError, match=r"not a finite number"):
        l.set_q(0, [float("nan"), 0, 0, 0])
    with pytest.raises(ValueError, match=r"effect_model: 3 probabilities given, the learner has 18 effects"):
        l.effect_model = [1.0, 0.0, 0.0]
    with pytest.raises(ValueError, match=r"summing to 1"):
        l.effect_model = np.full(18, 0.5)
    with pytest.raises(ValueError, match=r"policy of slot 1: expected probabilities > 0 summing to 1"):
        l.set_policy(1, [1.0, 0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"learner: scene `arm7`: the learner's slots have alphabet sizes \[4, 4, 4, 4, 4, 4, 4\] \(0: values\), the scene's \[3, 3, 3, 3, 3, 3, 3\]"):
        e3d.run_session("arm7", learner=l, trials=10)


def test_e3d_learner_saves_and_loads_bit_for_bit():
    l = e3d.E3dLearner("two_rooms", alpha=0.2, beta=3.0, eta=0.02)
    e3d.run_session("two_rooms", learner=l, trials=3000, seed=4)
    saved = l.to_bytes()
    back = e3d.E3dLearner.from_bytes(saved)
    unpickled = pickle.loads(pickle.dumps(l))
    assert back.to_bytes() == saved and unpickled.to_bytes() == saved and back == l
    # the loaded learners go on exactly as the original
    runs = [e3d.run_session("two_rooms", learner=x, trials=2000, seed=9) for x in (l, back, unpickled)]
    assert runs[0].effects.tolist() == runs[1].effects.tolist() == runs[2].effects.tolist()
    assert l.to_bytes() == back.to_bytes() == unpickled.to_bytes() != saved
    # as a Python learner (propose / learn) it is the same E3D
    py = e3d.E3dLearner.from_bytes(saved)
    native = e3d.E3dLearner.from_bytes(saved)
    a = e3d.run_session("two_rooms", learner=py.__class__.from_bytes(saved), trials=300, seed=2)
    b = e3d.run_session("two_rooms", learner=_AsPython(py), trials=300, seed=2)
    assert a.effects.tolist() == b.effects.tolist()
    e3d.run_session("two_rooms", learner=native, trials=300, seed=2)
    assert py.to_bytes() == native.to_bytes()
    for broken, msg in [(b"", "not a learner.s state"), (saved[:-5], "the bytes end early"),
                        (saved + b"x", "1 bytes after the state")]:
        with pytest.raises(ValueError, match=msg):
            e3d.E3dLearner.from_bytes(broken)


class _AsPython:
    """An E3dLearner driven through the Python learner interface."""

    def __init__(self, inner):
        self.inner = inner

    def propose(self, rng):
        return self.inner.propose(rng)

    def learn(self, command, effect, reward):
        self.inner.learn(command.tolist(), effect, reward)


def test_on_trials_hands_every_trial_in_batches():
    seen = []
    rec = e3d.run_session("two_rooms", trials=2500, seed=3, every=1000,
                          on_trials=lambda first, c, e, r: seen.append((first, c.copy(), e.copy(), r.copy())))
    assert [s[0] for s in seen] == [0, 1000, 2000] and [len(s[2]) for s in seen] == [1000, 1000, 500]
    assert np.concatenate([s[1] for s in seen]).tolist() == rec.commands.tolist()
    assert np.concatenate([s[2] for s in seen]).tolist() == rec.effects.tolist()
    assert np.concatenate([s[3] for s in seen]).tolist() == rec.rewards.tolist()
    # the same session as without the callback
    assert rec.effects.tolist() == e3d.run_session("two_rooms", trials=2500, seed=3).effects.tolist()
    # a Python learner too; an exception stops the session and is raised
    calls = []

    def stop(first, c, e, r):
        calls.append(first)
        if first >= 200:
            raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        e3d.run_session("two_rooms", trials=5000, every=100, on_trials=stop)
    assert calls == [0, 100, 200]
    with pytest.raises(ValueError, match="every = 0"):
        e3d.run_session("two_rooms", trials=10, every=0, on_trials=stop)
