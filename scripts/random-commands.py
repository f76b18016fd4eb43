#!/usr/bin/env python3
"""N distinct random commands of a scene whose slots share one alphabet.

    scripts/random-commands.py ALPHABET SLOTS N [SEED]

prints N distinct commands of SLOTS symbols from ALPHABET, one per line, in
a random order (Python's `random.Random(SEED)`, SEED 0 by default), for
`e3d scene exec SCENE -`. Example: the sample of docs/scenes.md,

    scripts/random-commands.py ESWN 14 20000 0 | e3d scene exec puck_rooms14 -
"""
import random
import sys


def main(argv):
    if len(argv) not in (3, 4):
        sys.exit(__doc__)
    alphabet, slots, n = argv[0], int(argv[1]), int(argv[2])
    seed = int(argv[3]) if len(argv) == 4 else 0
    total = len(alphabet) ** slots
    if not 0 < n <= total:
        sys.exit(f"N must be in 1..={total}")
    rng = random.Random(seed)
    out = []
    for index in rng.sample(range(total), n):
        symbols = []
        for _ in range(slots):
            index, k = divmod(index, len(alphabet))
            symbols.append(alphabet[k])
        out.append("".join(symbols))
    sys.stdout.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
