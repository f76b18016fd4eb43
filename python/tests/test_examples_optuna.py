"""The Optuna example (python/examples/optuna_alpha_beta.py) tunes E3D's
alpha and beta through the Python API; skipped without optuna."""

import importlib.util

import numpy as np
import pytest

import e3d

pytest.importorskip("optuna")


def load_example(root):
    spec = importlib.util.spec_from_file_location("optuna_alpha_beta", root / "python" / "examples" / "optuna_alpha_beta.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_optuna_tunes_alpha_and_beta(root):
    mod = load_example(root)
    study = mod.tune(n_trials=6, sessions=2, trials=1200)
    assert len(study.trials) == 6 and set(study.best_params) == {"alpha", "beta"}
    # the best value is the score of its parameters, recomputed
    p = study.best_params
    batch = e3d.run_sessions("two_rooms", trials=1200, sessions=2, seed=0, alpha=p["alpha"],
                             beta=p["beta"], use_reward=False)
    assert study.best_value == float(np.mean(batch.metrics["normalized_entropy_last_1000"]))
    assert study.best_value >= max(t.value for t in study.trials)
    # seeded: the same study again
    again = mod.tune(n_trials=6, sessions=2, trials=1200)
    assert again.best_params == study.best_params
