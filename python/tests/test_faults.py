"""Bad input and faults, round 4 of issue 48: results handed out read-only,
allocations that cannot be made raise MemoryError, loaded learner states
checked (checksum, NaN)."""

import pickle
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import e3d


def _assert_read_only(a):
    assert isinstance(a, np.ndarray)
    assert not a.flags.writeable
    with pytest.raises(ValueError, match="read-only"):
        a[...] = 0


def test_a_batchs_arrays_are_read_only():
    batch = e3d.run_sessions("two_rooms", trials=20, seeds=[1, 2])
    entropy = batch.metrics["normalized_entropy"]
    before = entropy.copy()
    with pytest.raises(ValueError, match="read-only"):
        batch.metrics["normalized_entropy"][0] = 99
    assert batch.metrics["normalized_entropy"].tolist() == before.tolist()
    for a in [batch.seeds, batch.commands, batch.effects, batch.rewards, *batch.metrics.values()]:
        _assert_read_only(a)
    for a in [batch[:1].effects, batch[0].rewards, batch[0].effect_counts]:
        _assert_read_only(a)
    # a copy is the user's to change
    mine = np.array(batch.rewards)
    mine[0, 0] = 5.0
    assert mine.flags.writeable


def test_a_records_arrays_are_read_only_also_when_unpickled():
    rec = e3d.run_session("two_rooms", trials=20)
    back = pickle.loads(pickle.dumps(rec))
    for r in (rec, back):
        for a in [r.commands, r.effects, r.rewards, r.effect_counts]:
            _assert_read_only(a)
        for p in r.final_policy or []:
            _assert_read_only(p)
    assert back == rec


def test_an_episode_records_arrays_are_read_only():
    rec = e3d.run_episodes("four_rooms", episodes=10, commands=2)
    for a in [rec.starts, rec.contexts, rec.commands, rec.effects, rec.rewards]:
        _assert_read_only(a)


def test_records_that_cannot_be_allocated_raise_memory_error():
    # in a child limited to 1 GiB of address space: 10^8 trials of a
    # 7-slot scene need about 4.6 GB of records; it aborted the interpreter
    code = textwrap.dedent(
        """
        import resource, e3d
        resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))
        try:
            e3d.run_session("two_rooms", trials=10**8)
        except MemoryError as e:
            print("MemoryError:", e)
        """
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "MemoryError: trials = 100000000" in out.stdout, out.stdout + out.stderr


def test_learner_states_are_checksummed():
    l = e3d.Learner("two_rooms", "e3d")
    data = l.to_bytes()
    assert data.startswith(b"E3D-LEARNER-STATE 3\n")
    e3d.Learner.from_bytes(data)
    bad = bytearray(data)
    bad[len(bad) // 2] ^= 1
    with pytest.raises(ValueError, match="checksum"):
        e3d.Learner.from_bytes(bytes(bad))


def fnv1a64(data):
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h.to_bytes(8, "little")


def test_a_nan_learning_rate_is_refused():
    data = e3d.Learner("two_rooms", "e3d").to_bytes()
    body = bytearray(data[:-8])
    # E3D's fields end with beta; the checksum made anew after the edit
    body[-8:] = np.float64("nan").tobytes()
    with pytest.raises(ValueError, match="NaN"):
        e3d.Learner.from_bytes(bytes(body) + fnv1a64(body))


def test_states_of_older_versions_are_refused_by_version():
    data = e3d.Learner("two_rooms", "e3d").to_bytes()
    old = b"E3D-LEARNER-STATE 2\n" + data[len(b"E3D-LEARNER-STATE 3\n"):]
    with pytest.raises(ValueError, match="format version 2 .*: this e3d reads version 3 only"):
        e3d.Learner.from_bytes(old)
