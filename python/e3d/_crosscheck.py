"""``e3d.crosscheck``: a physics scene run in e3d (Rapier) and in MuJoCo
on the same commands, through its MJCF export (``Scene.to_mjcf``). Needs
the ``mujoco`` package (``pip install 'e3d[mujoco]'``)."""

import math
from typing import Any, Union

import numpy as np
import numpy.typing as npt

from ._e3d import Scene


def _wrap(a: float) -> float:
    """An angle in [-pi, pi)."""
    return (a + math.pi) % (2 * math.pi) - math.pi


def _features(scene: Scene) -> list[tuple[str, dict[str, Any]]]:
    """The effect's features, in order: (kind, fields)."""
    (world,) = scene.to_dict()["world"].values()
    effect = world["effect"]
    if effect.get("features"):
        return [next(iter(f.items())) for f in effect["features"]]
    point = effect.get("point", [0.0, 0.0])
    return [("Point", {"body": effect["body"], "point": point, "frame": None})]


def _turn(angle: float, p: tuple[float, float]) -> tuple[float, float]:
    s, c = math.sin(angle), math.cos(angle)
    return c * p[0] - s * p[1], s * p[0] + c * p[1]


class _Mujoco:
    """The exported model, with the table of what each symbol does."""

    def __init__(self, scene: Scene) -> None:
        import mujoco  # type: ignore[import-not-found, import-untyped, unused-ignore]  # the optional extra

        self.mj = mujoco
        self.model = mujoco.MjModel.from_xml_string(scene.to_mjcf())
        self.data = mujoco.MjData(self.model)
        together, self.per, self.after, self.substeps = (
            int(x) for x in self.numeric("e3d_schedule"))
        self.together = together == 1
        self.scene = scene
        self.features = _features(scene)
        # e3d's drag (`e3d_drag_<body>`: along, across, turn), applied as
        # xfrc_applied (docs/mjcf.md)
        self.drags: list[tuple[int, npt.NDArray[np.float64]]] = []
        for i in range(self.model.nnumeric):
            name = mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_NUMERIC, i)
            if name.startswith("e3d_drag_"):
                body = self.model.body(name[len("e3d_drag_"):]).id
                self.drags.append((body, self.numeric(name)))

    def _drag(self) -> None:
        """Sets each dragged body's applied force and torque (world frame,
        at its centre of mass) from its state now, as e3d does at the start
        of each of its steps: -(along (v.u) u + across (v.n) n), -turn w."""
        mj, m, d = self.mj, self.model, self.data
        v6 = np.zeros(6)
        for b, (along, across, turn) in self.drags:
            # the body frame's velocity, then its centre of mass's
            mj.mj_objectVelocity(m, d, mj.mjtObj.mjOBJ_XBODY, b, v6, 0)
            w = v6[2]
            r = d.xipos[b] - d.xpos[b]
            vx, vy = v6[3] - w * r[1], v6[4] + w * r[0]
            c, s = d.xmat[b][0], d.xmat[b][3]
            a, n = c * vx + s * vy, -s * vx + c * vy
            fa, fn = -along * a, -across * n
            d.xfrc_applied[b] = [c * fa - s * fn, s * fa + c * fn, 0.0, 0.0, 0.0, -turn * w]

    def _step(self, k: int) -> int:
        """One MuJoCo step, the `k`-th of the command; the drag is set at
        the start of each e3d step."""
        if self.drags and k % self.substeps == 0:
            self._drag()
        self.mj.mj_step(self.model, self.data)
        return k + 1

    def numeric(self, name: str) -> npt.NDArray[np.float64]:
        return np.asarray(self.model.numeric(name).data, dtype=np.float64)

    def _slot(self, slot: int, value: Union[int, float], held: Any, impulse: Any,
              setpoint: Any) -> None:
        """Adds the controls of one slot's symbol (or value) to the arrays."""
        if self.scene.is_continuous:
            d = self.numeric(f"e3d_s{slot}_value")
            if d[0] == 4:  # an impulse in the direction of the value
                ax, ay, j = int(d[1]), int(d[2]), d[3]
                h = self.model.opt.timestep
                impulse[ax] += j * math.cos(value) / h
                impulse[ay] += j * math.sin(value) / h
                return
            scale = float(value)
        else:
            d = self.numeric(f"e3d_s{slot}_{int(value)}")
            scale = 1.0
        mode, pairs = int(d[0]), d[1:].reshape(-1, 2)
        for a, v in pairs:
            target = {1: held, 2: setpoint, 3: impulse}[mode]
            if mode == 2:
                target[int(a)] = v * scale
            else:
                target[int(a)] += v * scale

    def run(self, command: Any) -> tuple[list[float], bool]:
        """The feature values after `command` (a row of symbol indices or
        values), and whether any contact happened."""
        mj, m, d = self.mj, self.model, self.data
        mj.mj_resetData(m, d)
        setpoint = np.zeros(m.nu)
        contact = False
        slots = len(command)
        groups = [range(slots)] if self.together else [[s] for s in range(slots)]
        k = 0
        for group in groups:
            held, impulse = np.zeros(m.nu), np.zeros(m.nu)
            for s in group:
                self._slot(s, command[s], held, impulse, setpoint)
            for step in range(self.per):
                d.ctrl[:] = setpoint + held + (impulse if step == 0 else 0.0)
                k = self._step(k)
                contact = contact or d.ncon > 0
        for _ in range(self.after):
            d.ctrl[:] = setpoint
            k = self._step(k)
            contact = contact or d.ncon > 0
        return self.values(), contact

    def values(self) -> list[float]:
        mj, m, d = self.mj, self.model, self.data
        out: list[float] = []

        def pose(body: str) -> tuple[float, float, float]:
            b = m.body(body).id
            return d.xpos[b][0], d.xpos[b][1], math.atan2(d.xmat[b][3], d.xmat[b][0])

        for f, (kind, a) in enumerate(self.features):
            if kind == "Point":
                p = d.site(f"e3d_effect{f}").xpos
                x, y = p[0], p[1]
                if a.get("frame"):
                    fx, fy, fa = pose(a["frame"])
                    x, y = _turn(-fa, (x - fx, y - fy))
                out += [x, y]
            elif kind == "Centre":
                ids = [m.body(b).id for b in a["bodies"]]
                w = m.body_mass[ids]
                out += list(w @ d.xipos[ids, :2] / w.sum())
            elif kind == "Joint":
                j = m.joint(a["joint"])
                q = float(d.qpos[j.qposadr[0]])
                out.append(-_wrap(-q) if j.type[0] == mj.mjtJoint.mjJNT_HINGE else q)
            else:
                out.append(_wrap(pose(a["body"])[2]))
        return out


def _e3d_values(mj: _Mujoco, features: list[tuple[str, dict[str, Any]]],
                motion: Any) -> list[float]:
    """The feature values at the end of an e3d motion (``World.trace``); a
    centre of mass from the bodies' masses and centres the model holds
    (Rapier's)."""
    last = len(motion.time) - 1

    def pose(body: str) -> tuple[float, float, float]:
        b = motion.bodies.index(body)
        return motion.x[last, b], motion.y[last, b], motion.angle[last, b]

    out: list[float] = []
    for kind, a in features:
        if kind == "Point":
            bx, by, ba = pose(a["body"])
            dx, dy = _turn(ba, tuple(a["point"]))
            x, y = bx + dx, by + dy
            if a.get("frame"):
                fx, fy, fa = pose(a["frame"])
                x, y = _turn(-fa, (x - fx, y - fy))
            out += [x, y]
        elif kind == "Centre":
            c, total = np.zeros(2), 0.0
            for name in a["bodies"]:
                b = mj.model.body(name)
                bx, by, ba = pose(name)
                dx, dy = _turn(ba, (b.ipos[0], b.ipos[1]))
                c += b.mass[0] * np.array([bx + dx, by + dy])
                total += b.mass[0]
            out += list(c / total)
        elif kind == "Joint":
            out.append(float(motion.joint_angle[last, motion.joints.index(a["joint"])]))
        else:
            out.append(_wrap(pose(a["body"])[2]))
    return out


def crosscheck(
    scene: Union[Scene, str], commands: int = 200, seed: int = 0
) -> "dict[str, Union[npt.NDArray[Any], list[str]]]":
    """Runs `commands` random commands (drawn uniformly with numpy's
    generator of `seed`) of a physics scene in e3d and in MuJoCo (the
    scene's ``to_mjcf()`` model) and returns, per command, as a dict of
    columns: ``command`` (its text), ``distance`` (float64: the Euclidean
    distance between the two terminal values of the effect's features:
    metres for points, radians or metres for joints, radians for angles),
    ``agree`` (bool: the same effect cell), ``contact`` (bool: MuJoCo had a
    contact at some step), ``e3d_effect`` and ``mujoco_effect`` (int64).
    Needs the ``mujoco`` package; docs/mjcf.md has the figures of the
    shipped scenes."""
    if isinstance(scene, str):
        scene = Scene.resolve(scene)
    mj = _Mujoco(scene)
    rng = np.random.default_rng(seed)
    world = scene.world()
    if scene.is_continuous:
        lo, hi = np.array(scene.value_ranges).T
        rows: Any = lo + (hi - lo) * rng.random((commands, scene.num_slots))
    else:
        rows = np.stack([rng.integers(0, n, commands) for n in scene.alphabet_sizes], axis=1)
        rows = rows.astype(np.uint8)
    texts: list[str] = []
    distance = np.zeros(commands)
    agree = np.zeros(commands, dtype=bool)
    contact = np.zeros(commands, dtype=bool)
    ours = np.zeros(commands, dtype=np.int64)
    theirs = np.zeros(commands, dtype=np.int64)
    for i, row in enumerate(rows):
        motion = world.trace(row)
        texts.append(motion.command)
        mine = _e3d_values(mj, mj.features, motion)
        values, contact[i] = mj.run(row)
        diffs = [a - b for a, b in zip(mine, values)]
        for f, (kind, a) in enumerate(mj.features):
            angular = kind == "Angle" or (kind == "Joint" and _is_hinge(mj, a["joint"]))
            if angular:
                at = sum(2 if k in ("Point", "Centre") else 1 for k, _ in mj.features[:f])
                diffs[at] = _wrap(diffs[at])
        distance[i] = math.sqrt(sum(x * x for x in diffs))
        ours[i] = motion.outcome.effect
        theirs[i] = scene.effect_of(values)
        agree[i] = ours[i] == theirs[i]
    return {"command": texts, "distance": distance, "agree": agree, "contact": contact,
            "e3d_effect": ours, "mujoco_effect": theirs}


def _is_hinge(mj: _Mujoco, joint: str) -> bool:
    return bool(mj.model.joint(joint).type[0] == mj.mj.mjtJoint.mjJNT_HINGE)
