"""e3d: a 2D physics sandbox (Rapier) for learning compositional motor
commands by End-Effect Exploration Drive (E3D, after E. Daucé 2020).

The Rust library does all the work; this package hands numpy arrays in and
out::

    import numpy as np, e3d
    scene = e3d.Scene.builtin("puck_rooms")        # or e3d.Scene.load("scenes/puck_rooms.ron")
    world = scene.world()
    out = world.execute_batch(scene.parse(["EESSEES", "SEEEEES"]))
    out.effect, out.reward, out.x, out.y           # numpy arrays, one entry per command
    rec = e3d.run_session(scene, learner="e3d", trials=5000, seed=0)
    rec.effects, rec.metrics["normalized_entropy"]

``e3d.gym`` holds a Gymnasium environment (it imports gymnasium; this
module does not). See docs/python.md in the repository.
"""

from ._e3d import (
    E3D_VERSION,
    BatchOutcome,
    Outcome,
    Scene,
    SceneError,
    SessionRecord,
    SessionRng,
    SimulationError,
    World,
    __version__,
    run_session,
    run_sweep,
)

__all__ = [
    "E3D_VERSION",
    "BatchOutcome",
    "Outcome",
    "Scene",
    "SceneError",
    "SessionRecord",
    "SessionRng",
    "SimulationError",
    "World",
    "__version__",
    "run_session",
    "run_sweep",
]
