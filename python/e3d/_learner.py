"""``Learner`` and ``E3dLearner``: a built-in learner's state, its tables
by name, pickling and equality over the native base ``_Learner`` (which
makes, steps, saves and loads it); ``E3dLearner`` reads and writes E3D's in
its own words, Q and the policy per slot and the effect model."""

import copyreg
from typing import Any, Iterator, Sequence

import numpy as np
import numpy.typing as npt

from ._e3d import _E3dLearner, _Learner


class Learner(_Learner):
    """A built-in learner (``"e3d"``, ``"e3d_relax"``, ``"count"``, ``"smm"``,
    ``"egreedy"``, ``"uniform"``, ``"goal_babbling"``, ``"archive"``,
    ``"archive_reached"``, ``"map_elites"``; on a continuous scene the
    Gaussian ``"e3d"``, ``"uniform"``, ``"goal_babbling"``, ``"archive"``,
    ``"archive_reached"`` or ``"map_elites"`` values; with contexts, from
    ``Learner.contextual``) as a state: its tables by name (``l["q"]``,
    ``l["target"] = ...``), stepped by ``propose`` / ``learn``, saved as
    bytes bit for bit (``to_bytes``, ``Learner.from_bytes``, pickling) and
    read back as a learner that goes on exactly as this one would.
    ``run_session(scene, learner=l)`` (with contexts ``run_episodes``) runs
    from ``l``'s state and leaves ``l`` in the state it ends in."""

    __slots__ = ()
    __module__ = "e3d"

    @staticmethod
    def from_bytes(data: bytes) -> "Learner":
        """A learner from the bytes of ``to_bytes`` (an ``E3dLearner``'s too),
        whatever its kind (``ValueError`` saying what is wrong if they are not)."""
        return Learner(data)

    def _table(self, name: str) -> tuple[str, list[int], npt.NDArray[np.float64], bool]:
        """The table ``name``, or a ``KeyError`` naming the learner's tables."""
        if not isinstance(name, str):
            raise TypeError(f"argument 'name': '{type(name).__name__}' object cannot be cast as 'str'")
        tables = self._tables()
        for t in tables:
            if t[0] == name:
                return t
        names = ", ".join(f"'{t[0]}'" for t in tables)
        raise KeyError(f"a `{self.kind}` learner has no table '{name}' (its tables: [{names}])")

    def keys(self) -> list[str]:
        """The names of the learner's tables (``"q"``, ``"policy"``, ``"p"``,
        ``"target"``, ``"counts"``, ... as it has them), in order."""
        return [t[0] for t in self._tables()]

    @property
    def writable(self) -> list[str]:
        """The names of the tables that ``learner[name] = array`` can write."""
        return [t[0] for t in self._tables() if t[3]]

    def __contains__(self, name: object) -> bool:
        """Whether the learner has a table of that name (``"q" in learner``)."""
        return isinstance(name, str) and name in self.keys()

    def __iter__(self) -> Iterator[str]:
        """The names of the tables, as ``keys()`` (``list(learner)``)."""
        return iter(self.keys())

    def __getitem__(self, name: str) -> npt.NDArray[np.float64]:
        """The table ``name`` as a float64 array (a copy), e.g. ``l["q"]``
        ``(slots, k)``, ``l["p"]`` ``(effects,)``; ``KeyError`` naming the
        tables there are if it has none of that name."""
        _, shape, values, _ = self._table(name)
        return values.reshape(shape)

    def __setitem__(self, name: str, value: npt.ArrayLike) -> None:
        """Replaces the table ``name`` by ``value`` (an array of its shape):
        ``ValueError`` naming the table if the shape, a value or the table's
        rules do not fit (the learner is then unchanged)."""
        shape = tuple(self._table(name)[1])
        try:
            a = np.asarray(value, "float64", "C")
        except Exception:
            raise ValueError(f"learner['{name}']: expected an array of numbers") from None
        if a.shape != shape:
            raise ValueError(f"learner['{name}']: expected an array of shape {shape!r}, "
                             f"found {a.shape!r}")
        self._set_table(name, a.ravel())

    def __eq__(self, other: object) -> bool:
        """Equal: learners whose saved bytes are equal."""
        return isinstance(other, _Learner) and other.to_bytes() == self.to_bytes()

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickling: the bytes of ``to_bytes``, read back by ``from_bytes``; an
        instance of a subclass (``E3dLearner`` too) comes back as one of that
        class, its ``__dict__`` with it (``copyreg.__newobj__(cls, data)``,
        then the dict)."""
        data = self.to_bytes()
        if type(self) is Learner:
            return (Learner.from_bytes, (data,))
        newobj = copyreg.__newobj__  # type: ignore[attr-defined]
        return (newobj, (type(self), data), getattr(self, "__dict__", None))


class E3dLearner(_E3dLearner, Learner):
    """An E3D learner (the paper's Algorithm 1) for a scene of symbols: an
    ``e3d.Learner`` of kind ``"e3d"`` whose Q table, policy and effect model
    also read and write per slot. Saving, loading, pickling, ``propose`` /
    ``learn``, the tables by name and ``run_session(learner=...)`` are
    ``Learner``'s."""

    __slots__ = ()
    __module__ = "e3d"

    @staticmethod
    def from_bytes(data: bytes) -> "E3dLearner":
        """A learner from the bytes of ``to_bytes`` (``ValueError`` if they
        are not an E3D learner's)."""
        return E3dLearner(data)

    def _per_slot(self, table: str) -> list[npt.NDArray[np.float64]]:
        """The rows of a table ``(slots, k)`` cut to each slot's alphabet
        (the entries past it are NaN)."""
        return [row[~np.isnan(row)] for row in self[table]]

    @property
    def alphabet_sizes(self) -> list[int]:
        """The alphabet size of each slot."""
        return [len(q) for q in self._per_slot("q")]

    @property
    def num_effects(self) -> int:
        """The number of effects."""
        return len(self["p"])

    @property
    def q(self) -> list[npt.NDArray[np.float64]]:
        """``Q``, one float64 array per slot (copies: write with ``set_q`` or
        by assigning the whole list)."""
        return self._per_slot("q")

    @q.setter
    def q(self, value: Sequence[Sequence[float]]) -> None:
        rows, n = list(value), len(self.alphabet_sizes)
        if len(rows) != n:
            raise ValueError(f"q: {len(rows)} slots given, the learner has {n}")
        # written to a copy first: a slot refused leaves the learner unchanged
        for learner in (E3dLearner(self.to_bytes()), self):
            for slot, q in enumerate(rows):
                learner.set_q(slot, q)

    @property
    def policy(self) -> list[npt.NDArray[np.float64]]:
        """The policy, one array per slot: ``softmax(beta Q[:, slot])``."""
        return self._per_slot("policy")

    @property
    def effect_model(self) -> npt.NDArray[np.float64]:
        """The effect model ``p``, the running histogram of effects (a copy;
        assign an array of ``num_effects`` probabilities to replace it)."""
        return self["p"]

    @effect_model.setter
    def effect_model(self, value: Sequence[float]) -> None:
        self._set_effect_model(value)

    def __repr__(self) -> str:
        sizes = self.alphabet_sizes
        return f"E3dLearner({len(sizes)} slots of sizes {sizes}, {self.num_effects} effects)"
