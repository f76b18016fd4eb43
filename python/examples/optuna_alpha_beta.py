"""Tuning E3D's alpha and beta with Optuna, through the Python API.

Each Optuna trial runs `e3d.run_sessions` (several seeds in lockstep,
without the GIL) with the trial's alpha and beta, and scores them by the
mean normalized entropy of the effects over the last 1000 trials (the
metric `normalized_entropy_last_1000`: how evenly the learnt policy
spreads its effects). The sampler is seeded, so the study is
reproducible.

    python python/examples/optuna_alpha_beta.py [N_TRIALS] [SESSIONS] [TRIALS]

prints the best alpha and beta and their score. Needs `pip install optuna`.
"""

import sys

import numpy as np
import optuna

import e3d


def objective(trial, scene, sessions, trials):
    alpha = trial.suggest_float("alpha", 0.01, 1.0, log=True)
    beta = trial.suggest_float("beta", 0.1, 100.0, log=True)
    batch = e3d.run_sessions(scene, learner="e3d", trials=trials, sessions=sessions, seed=0,
                             alpha=alpha, beta=beta, use_reward=False)
    return float(np.mean(batch.metrics["normalized_entropy_last_1000"]))


def tune(n_trials=20, sessions=4, trials=3000, scene="two_rooms", seed=0):
    """The finished study: `study.best_params` holds the best alpha and beta."""
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    scene = e3d.Scene.resolve(scene) if isinstance(scene, str) else scene
    study = optuna.create_study(direction="maximize", sampler=optuna.samplers.TPESampler(seed=seed))
    study.optimize(lambda t: objective(t, scene, sessions, trials), n_trials=n_trials)
    return study


def main(argv):
    n_trials = int(argv[0]) if argv else 20
    sessions = int(argv[1]) if len(argv) > 1 else 4
    trials = int(argv[2]) if len(argv) > 2 else 3000
    study = tune(n_trials, sessions, trials)
    p = study.best_params
    print(f"best alpha = {p['alpha']:.4g}, beta = {p['beta']:.4g}: "
          f"normalized_entropy_last_1000 = {study.best_value:.4f} ({n_trials} trials)")


if __name__ == "__main__":
    main(sys.argv[1:])
