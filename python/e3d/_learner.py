"""``E3dLearner``: an ``e3d.Learner`` of kind ``"e3d"`` read and written in
E3D's own words, Q and the policy per slot and the effect model; its native
base ``_E3dLearner`` makes it and writes it, ``Learner``'s tables read it."""

from typing import Sequence

import numpy as np
import numpy.typing as npt

from ._e3d import _E3dLearner


class E3dLearner(_E3dLearner):
    """An E3D learner (the paper's Algorithm 1) for a scene of symbols: an
    ``e3d.Learner`` of kind ``"e3d"`` whose Q table, policy and effect model
    also read and write per slot. Saving, loading, pickling, ``propose`` /
    ``learn``, the tables by name and ``run_session(learner=...)`` are
    ``Learner``'s."""

    __slots__ = ()

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
