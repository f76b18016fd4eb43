"""Every built-in learner's state from Python: `e3d.Learner` saved by
`to_bytes` / pickling and loaded back goes on with the same bytes as the
learner that never stopped."""

import pickle

import numpy as np

import pytest

import e3d

# these tests give every learner the same hyper-parameters: the warnings
# for those a learner does not read are expected
pytestmark = pytest.mark.filterwarnings("ignore:.* does nothing:UserWarning")

SYMBOL_KINDS = ["e3d", "e3d_relax", "count", "smm", "egreedy", "uniform", "goal_babbling", "archive",
                "archive_reached", "map_elites"]


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
    for kind, saved_kind in [("e3d", "gaussian_e3d"), ("uniform", "uniform_values"),
                             ("goal_babbling", "goal_babbling_values"), ("archive", "archive_values"),
                             ("archive_reached", "archive_reached_values"),
                             ("map_elites", "map_elites_values")]:
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
    with pytest.raises(ValueError, match="learner `archive`: no saved state per context"):
        e3d.Learner.contextual("two_rooms", "archive")
    with pytest.raises(ValueError, match="the bytes hold the state of a `goal_babbling` learner"):
        e3d.E3dLearner.from_bytes(e3d.Learner("two_rooms", "goal_babbling").to_bytes())
    with pytest.raises(ValueError, match="learner: "):
        e3d.Learner("two_rooms", "nope")
    with pytest.raises(ValueError, match="eta = 2"):
        e3d.Learner("two_rooms", "e3d", eta=2.0)


def _hand_loop(scene, learner, trials, seed):
    """propose / execute / learn in a loop of one's own."""
    world = e3d.Scene.resolve(scene).world() if isinstance(scene, str) else scene.world()
    rng = e3d.SessionRng(seed)
    commands, effects, rewards = [], [], []
    for t in range(trials):
        c = learner.propose(rng)
        o = world.execute(c)
        if t % 2:
            learner.learn(c, o)  # the outcome: effect, reward and terminal point
        else:
            learner.learn(c, o.effect, o.reward, point=(o.x, o.y))
        commands.append(c)
        effects.append(o.effect)
        rewards.append(o.reward)
    return np.array(commands), effects, rewards


@pytest.mark.parametrize("kind", ["e3d", "egreedy", "count", "smm", "goal_babbling", "archive"])
def test_a_hand_loop_is_run_session_bit_for_bit(kind):
    by_hand = e3d.Learner("two_rooms", kind, epsilon=0.2)
    e3d.run_session("two_rooms", learner=by_hand, trials=300, seed=1)  # not a fresh state
    session = e3d.Learner.from_bytes(by_hand.to_bytes())
    commands, effects, rewards = _hand_loop("two_rooms", by_hand, 700, seed=5)
    rec = e3d.run_session("two_rooms", learner=session, trials=700, seed=5)
    assert commands.tolist() == rec.commands.tolist()
    assert effects == rec.effects.tolist() and rewards == rec.rewards.tolist()
    assert sum(r > 0 for r in rewards) > 0  # the goal was reached: rewards were learned from
    assert by_hand.to_bytes() == session.to_bytes()


def test_tables_by_name_read_and_write():
    l = e3d.Learner("two_rooms", "e3d", beta=2.0)
    assert l.keys() == ["q", "policy", "p", "target"] and l.writable == l.keys()
    assert l["q"].shape == (7, 4) and l["p"].shape == (18,) and l["policy"][0].tolist() == [0.25] * 4
    e3d.run_session("two_rooms", learner=l, trials=500, seed=3)
    e = e3d.E3dLearner.from_bytes(l.to_bytes())
    assert np.array_equal(l["q"], np.array([q for q in e.q]))
    assert np.array_equal(l["p"], e.effect_model)
    # p*: set as weights, normalised; the drive follows it
    t = np.zeros(18)
    t[4] = 3.0
    t[5] = 1.0
    l["target"] = t
    assert l["target"][4] == 0.75 and l["target"][5] == 0.25
    assert l["target"][0] < 1e-10  # a weight 0 is floored, not -inf
    # the policy written: Q = log(p) / beta, and the policy read back
    pol = np.full((7, 4), 0.1)
    pol[:, 2] = 0.7
    l["policy"] = pol
    assert np.allclose(l["policy"], pol, rtol=0, atol=1e-12)
    assert np.allclose(l["q"][0], np.log(pol[0]) / 2.0, rtol=0, atol=1e-12)
    rng = e3d.SessionRng(1)
    drawn = np.array([l.propose(rng) for _ in range(400)])  # propose alone learns nothing
    assert 0.65 < (drawn == 2).mean() < 0.75  # 2800 draws of p = 0.7: sd 0.009
    before = l.to_bytes()
    for name, value, msg in [
        ("q", np.zeros(4), r"learner\['q'\]: expected an array of shape \(7, 4\), found \(4,\)"),
        ("q", np.full((7, 4), np.nan), r"learner\['q'\]: table `q`, slot 0: NaN is not a finite number"),
        ("policy", np.full((7, 4), 0.3), r"learner\['policy'\]: table `policy`, slot 0: expected probabilities > 0 summing to 1"),
        ("p", np.full(18, 0.5), r"learner\['p'\]: table `p`: "),
        ("target", -np.ones(18), r"learner\['target'\]: table `target`: "),
        ("p", "abc", r"learner\['p'\]: expected an array of numbers"),
    ]:
        with pytest.raises(ValueError, match=msg):
            l[name] = value
    assert l.to_bytes() == before  # nothing written
    with pytest.raises(KeyError, match=r"a `e3d` learner has no table 'counts' \(its tables: \['q', 'policy', 'p', 'target'\]\)"):
        l["counts"]


def test_every_kind_shows_its_tables():
    shown = {k: e3d.Learner("two_rooms", k).keys() for k in SYMBOL_KINDS}
    assert shown == {"e3d": ["q", "policy", "p", "target"], "e3d_relax": ["q", "policy", "p", "target"],
                     "count": ["q", "policy", "counts"], "smm": ["q", "policy", "counts", "target"],
                     "egreedy": ["q", "policy"], "uniform": [], "goal_babbling": [], "archive": [],
                     "archive_reached": [], "map_elites": []}
    c = e3d.Learner("two_rooms", "count")
    rec = e3d.run_session("two_rooms", learner=c, trials=300, seed=2)
    assert c["counts"].tolist() == np.bincount(rec.effects, minlength=18).tolist()
    c["counts"] = np.zeros(18)
    assert c["counts"].sum() == 0
    with pytest.raises(ValueError, match=r"table `counts`: 0.5 is not an integer >= 0"):
        c["counts"] = np.full(18, 0.5)
    s = e3d.Learner("two_rooms", "smm")
    with pytest.raises(ValueError, match=r"learner\['counts'\]: table `counts` of a `smm` learner is read-only"):
        s["counts"] = np.zeros(18)
    g = e3d.Learner("two_rooms", "egreedy")
    g["q"] = np.eye(7, 4)
    assert g["policy"][0].tolist() == [0.1 / 4 + 0.9, 0.1 / 4, 0.1 / 4, 0.1 / 4]
    with pytest.raises(ValueError, match=r"read-only"):
        g["policy"] = g["policy"]
    # the Gaussian E3D: mean and sd per slot (unit coordinates), p, target, baseline
    v = e3d.Learner("arm7_continuous")
    assert v.keys() == ["mean", "sd", "p", "target", "baseline"] and v["baseline"].shape == ()
    v["mean"] = np.full(7, 0.5)
    v["sd"] = np.full(7, 1e-9)
    rng = e3d.SessionRng(1)
    values = v.propose(rng)
    assert values.dtype == np.float64 and values.shape == (7,)
    # unit coordinate 0.5 of each slot's range [-t, t]: half of arm7's torques
    assert np.allclose(values, [0.9, 0.6, 0.375, 0.225, 0.12, 0.06, 0.03], rtol=0, atol=1e-6)
    with pytest.raises(ValueError, match=r"table `sd`: 0 is not a finite number > 0"):
        v["sd"] = np.zeros(7)


def test_propose_and_learn_refuse_what_does_not_fit():
    l = e3d.Learner("two_rooms", "count")
    with pytest.raises(ValueError, match=r"effect 18: expected an effect in \[0, 18\)"):
        l.learn([0] * 7, 18, 0.0)
    with pytest.raises(ValueError, match=r"command: expected one symbol index per slot, within the alphabet sizes \[4, 4, 4, 4, 4, 4, 4\]"):
        l.learn([0] * 6, 0, 0.0)
    with pytest.raises(ValueError, match=r"command: expected one symbol index per slot"):
        l.learn([4] * 7, 0, 0.0)
    with pytest.raises(ValueError, match=r"seed = -1"):
        e3d.SessionRng(-1)


CONTEXTS = "scenes/two_rooms_contexts.ron"  # two start contexts, no reward


def _episodes_of(root, closed_loop):
    """The scene and commands per episode of a test: two start contexts, or
    for the closed loop two_rooms' reward, 2 commands per episode."""
    return (root / CONTEXTS, 1) if not closed_loop else ("two_rooms", 2)


def _contextual(root, kind, closed_loop):
    scene, k = _episodes_of(root, closed_loop)
    return e3d.Learner.contextual(scene, kind, commands=k, closed_loop=closed_loop, epsilon=0.2)


@pytest.mark.parametrize("kind,closed_loop,name", [
    ("e3d", False, "e3d"), ("count", False, "count"), ("smm", False, "smm"),
    ("e3d", True, "e3d_closed_loop"), ("egreedy", True, "qlearning")])
def test_contextual_states_save_load_and_continue(root, kind, closed_loop, name):
    scene, k = _episodes_of(root, closed_loop)
    l = _contextual(root, kind, closed_loop)
    assert l.name == name
    # from a fresh state: the numbers of the built-in learner
    first = e3d.run_episodes(scene, episodes=300, commands=k, seed=1, learner=l,
                             closed_loop=closed_loop, epsilon=0.2)
    ref = e3d.run_episodes(scene, episodes=300, commands=k, seed=1, learner=kind,
                           closed_loop=closed_loop, epsilon=0.2)
    assert first.learner == ref.learner == name
    assert first.commands.tolist() == ref.commands.tolist() and first.effects.tolist() == ref.effects.tolist()
    if closed_loop:
        assert first.cumulative_reward > 0  # something to learn from
    saved = l.to_bytes()
    back, unpickled = e3d.Learner.from_bytes(saved), pickle.loads(pickle.dumps(l))
    assert back == l == unpickled
    runs = [e3d.run_episodes(scene, episodes=200, commands=k, seed=2, learner=x,
                             closed_loop=closed_loop) for x in (l, back, unpickled)]
    assert runs[0].commands.tolist() == runs[1].commands.tolist() == runs[2].commands.tolist()
    assert runs[0].effects.tolist() == runs[1].effects.tolist() == runs[2].effects.tolist()
    assert l.to_bytes() == back.to_bytes() == unpickled.to_bytes() != saved
    # going on is not starting afresh
    fresh = e3d.run_episodes(scene, episodes=200, commands=k, seed=2, learner=kind,
                             closed_loop=closed_loop, epsilon=0.2)
    assert fresh.commands.tolist() != runs[0].commands.tolist()


def test_a_hand_loop_of_episodes_is_run_episodes_bit_for_bit():
    # closed-loop E3D on two_rooms, 2 commands per episode, the cell
    # observed; one start (no draw for it), then each command from the last
    l = e3d.Learner.contextual("two_rooms", "e3d", commands=2, closed_loop=True)
    session = e3d.Learner.from_bytes(l.to_bytes())
    ew = e3d.EpisodeWorld("two_rooms", commands=2, closed_loop=True)
    assert ew.num_starts == 1
    rng = e3d.SessionRng(4)
    commands, effects, rewards = [], [], []
    for _ in range(400):
        context = ew.reset(start=0)
        done = False
        while not done:
            c = l.propose(context, rng)
            nxt, o, done = ew.step(c)
            l.learn(context, c, o.effect, o.reward, None if done else nxt)
            commands.append(c)
            effects.append(o.effect)
            rewards.append(o.reward)
            context = nxt
    rec = e3d.run_episodes("two_rooms", episodes=400, commands=2, seed=4, learner=session,
                           closed_loop=True)
    assert np.array(commands).tolist() == rec.commands.tolist()
    assert effects == rec.effects.tolist() and rewards == rec.rewards.tolist()
    assert sum(rewards) > 0
    assert l.to_bytes() == session.to_bytes()


def test_a_hand_loop_of_episodes_with_starts_drawn_from_the_learners_generator(root):
    # two start contexts: reset(rng=...) draws the start from the
    # generator the learner proposes from, as run_episodes does
    path = root / CONTEXTS
    l = e3d.Learner.contextual(path, "e3d", commands=2, closed_loop=True)
    session = e3d.Learner.from_bytes(l.to_bytes())
    ew = e3d.EpisodeWorld(path, commands=2, closed_loop=True)
    assert ew.num_starts == 2
    rng = e3d.SessionRng(4)
    starts, effects = [], []
    for _ in range(300):
        context = ew.reset(rng=rng)
        starts.append(ew.start)
        done = False
        while not done:
            c = l.propose(context, rng)
            nxt, o, done = ew.step(c)
            l.learn(context, c, o.effect, o.reward, None if done else nxt)
            effects.append(o.effect)
            context = nxt
    rec = e3d.run_episodes(path, episodes=300, commands=2, seed=4, learner=session, closed_loop=True)
    assert starts == rec.starts.tolist() and 0 < sum(starts) < 300
    assert effects == rec.effects.tolist()
    assert l.to_bytes() == session.to_bytes()
    with pytest.raises(ValueError, match="either seed or rng"):
        ew.reset(seed=1, rng=rng)
    with pytest.raises(TypeError, match="rng: expected an e3d.SessionRng"):
        ew.reset(rng=4)


class Tagged(e3d.Learner):
    """A user's subclass, with attributes of its own."""


def test_a_subclass_pickles_and_copies_as_itself():
    import copy
    t = Tagged("two_rooms", "count")
    t.tag = [1, 2]
    e3d.run_session("two_rooms", learner=t, trials=50, seed=1)
    for back in (pickle.loads(pickle.dumps(t)), copy.copy(t), copy.deepcopy(t)):
        assert type(back) is Tagged and back.tag == [1, 2]
        assert back.to_bytes() == t.to_bytes() and back == t
    assert e3d.Learner(t.to_bytes()) == t
    assert type(pickle.loads(pickle.dumps(e3d.E3dLearner("two_rooms")))) is e3d.E3dLearner


def test_learn_refusals():
    gb = e3d.Learner("two_rooms", "goal_babbling")
    c = gb.propose(e3d.SessionRng(0))
    with pytest.raises(ValueError, match="point: a goal_babbling learner learns from the terminal point"):
        gb.learn(c, 3, 0.0)
    with pytest.raises(TypeError, match="outcome: expected an e3d.Outcome"):
        gb.learn(c, 3)
    with pytest.raises(ValueError, match=r"point = \(NaN, 1\): expected finite numbers"):
        gb.learn(c, 3, 0.0, point=(float("nan"), 1.0))
    # continuous: values outside their ranges are refused, the learner unchanged
    g = e3d.Learner("arm7_continuous")
    before = g.to_bytes()
    with pytest.raises(ValueError, match="value 100 at slot 0 is outside its range"):
        g.learn(np.full(7, 100.0), 3, 0.0)
    assert g.to_bytes() == before
    # a Learner holds one session: run_sessions refuses it by name
    with pytest.raises(TypeError, match="an e3d.Learner holds one session's state"):
        e3d.run_sessions("two_rooms", learner=e3d.Learner("two_rooms"), trials=3, seeds=[0, 1])
    l = e3d.Learner("two_rooms")
    assert "q" in l and "nope" not in l and 3 not in l and list(l) == l.keys()
    with pytest.raises(ValueError, match=r"keys 0 and \(0, 0\) are the same effect 0"):
        e3d.Learner("two_rooms", target={0: 1.0, (0, 0): 2.0, 1: 1.0})
    with pytest.raises(ValueError, match="found -0.1 for effect 0"):
        e3d.E3dLearner("two_rooms").effect_model = np.r_[-0.1, 1.1, np.zeros(16)]


def test_contextual_tables_and_misfits(root):
    l = e3d.Learner.contextual(root / CONTEXTS, "e3d", commands=2, closed_loop=True)
    assert l.keys() == ["q", "policy", "p", "target", "reference"]
    assert l["q"].shape == (18, 7, 4) and l["p"].shape == (18, 18) and l["reference"].shape == (18, 4 ** 7)
    t = np.ones((18, 18))
    t[3] = 0.0
    t[3, 5] = 1.0
    l["target"] = t  # p*(e|s): one row per context
    assert l["target"][3, 5] == 1.0 and abs(l["target"][0, 0] - 1 / 18) < 1e-15
    with pytest.raises(ValueError, match=r"learner\['target'\]: context 2: table `target`: "):
        bad = np.ones((18, 18))
        bad[2] = -1.0
        l["target"] = bad
    assert abs(l["target"][2, 0] - 1 / 18) < 1e-15  # all or nothing
    q = e3d.Learner.contextual(root / CONTEXTS, "egreedy", commands=2, closed_loop=True)
    assert q.keys() == ["q"] and q["q"].shape == (18, 4 ** 7)
    open_loop = e3d.Learner.contextual(root / CONTEXTS, "count")  # one command: the start context observed
    assert open_loop["counts"].shape == (2, 18)
    with pytest.raises(ValueError, match=r"learner: scene `two_rooms_contexts`: the learner has 2 contexts, the run 18 contexts"):
        e3d.run_episodes(root / CONTEXTS, episodes=5, commands=2, seed=1, learner=open_loop)
    with pytest.raises(ValueError, match=r"the learner has 2 contexts, the run no contexts"):
        e3d.run_session(root / CONTEXTS, learner=open_loop, trials=5)
    with pytest.raises(ValueError, match=r"an e3d.Learner runs one seed"):
        e3d.run_episodes(root / CONTEXTS, episodes=5, seeds=[1, 2], learner=open_loop)
    with pytest.raises(ValueError, match=r"learner `count`: the closed loop takes e3d"):
        e3d.Learner.contextual(root / CONTEXTS, "count", closed_loop=True)
    with pytest.raises(TypeError, match=r"propose\(context, rng\)"):
        open_loop.propose(e3d.SessionRng(1))
    with pytest.raises(ValueError, match=r"context 2: expected a context in \[0, 2\)"):
        open_loop.learn(2, [0] * 7, 0, 0.0)
