"""How often Alg. 2 puts the CoM in the wrong block of a two-block object (exact senses).

Run: ``python benchmarks/accuracy/alg2_two_blobs.py [--seeds 400:600] [--pushes 30] [--cone 0.3]``.
The part ranking of ``estimate_progressive`` was chosen on seeds 0:400; report on
others.

The mask is two blocks, 25 x 30 and 19 x 20 pixels, 6 pixels apart, joined by a bar
6 x 4 pixels along the smaller one's bottom (one object: the estimators refuse a mask of
separate parts), so a final region high up falls apart. Each seed draws a true CoM
uniformly over the blocks' pixels, ``--pushes`` candidate pushes
(:func:`comcore.sample_pushes`) and their motions from the tests' toy physics: the
Voting Theorem's sense at mu = 0.5 and 0.02 rad per pixel of lever arm (so the
senses are exact). A trial is wrong when the estimate lies outside the block that
holds the true CoM (on the bar, too: a final region joined through it has its mean
there, and no part to choose). It is counted for the part choice
``estimate_progressive`` makes and for the paper's largest-area choice on the same
final region (the intersection of the applied cuts, which the part choice does not
change).
"""

from __future__ import annotations

import argparse

import numpy as np

import comcore

GAIN = 0.02  # rad per pixel of lever arm
MU = 0.5


def two_blocks() -> np.ndarray:
    """The blocks' labels: 1 and 2, the bar joining them 0 (as the background)."""
    img = np.zeros((40, 60), int)
    img[5:35, 5:30] = 1
    img[10:30, 36:55] = 2
    return img


def joined(blocks: np.ndarray) -> np.ndarray:
    """The object: the blocks and the bar along the smaller one's bottom rows."""
    img = blocks > 0
    img[26:30, 30:36] = True
    return img


def exact_motions(mask, actions, com):
    """The Voting Theorem's sense for ``com``, magnitude growing with the lever arm."""
    con = comcore.geometry.contacts(mask, actions)
    direction = actions[:, 2:] - actions[:, :2]
    sense = np.array(
        [
            comcore.vt.predicted_sense(com, con.point[i], con.normal[i], direction[i], MU)
            for i in range(len(actions))
        ]
    )
    lever = np.abs(comcore.geometry.signed_line_distance([com], actions)[0])
    return np.column_stack([sense * GAIN * lever, np.zeros(len(actions)), np.zeros(len(actions))])


def trial(seed: int, n_pushes: int, cone: float):
    """``(evidence rule wrong, largest-area rule wrong, final region in both blocks, one part)``.

    The last: the final region is one 8-connected part (through the bar), so there is
    no part to choose and both rules return it.
    """
    blocks = two_blocks()
    mask = comcore.Mask(joined(blocks), resolution=0.0025)
    rng = np.random.default_rng(seed)
    on_blocks = np.column_stack(np.nonzero(blocks)[::-1]).astype(float)  # (x, y), row-major
    com = on_blocks[rng.integers(len(on_blocks))]
    actions = comcore.sample_pushes(mask, n_pushes, cone=cone, rng=rng)
    motions = exact_motions(mask, actions, com)
    est = comcore.estimate_progressive(mask, actions, motions)
    truth = blocks[int(com[1]), int(com[0])]
    used = list(est.used)
    final = mask.data.copy()
    if used:
        final &= comcore.vt.region(mask, actions[used], motions[used]).all(axis=0)
    assert final.sum() == est.progressive.region_sizes[-1]

    def wrong(region):
        rows, cols = np.nonzero(region)
        x, y = int(np.rint(cols.mean())), int(np.rint(rows.mean()))
        return blocks[y, x] != truth

    two_parts = len(np.unique(blocks[final & (blocks > 0)])) > 1
    one_part = comcore.geometry.largest_component(final).sum() == final.sum()
    return (
        wrong(est.region), wrong(comcore.geometry.largest_component(final)), two_parts, one_part
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="400:600", help="first:last (exclusive)")
    parser.add_argument("--pushes", type=int, default=30)
    parser.add_argument("--cone", type=float, default=0.3)
    args = parser.parse_args(argv)
    first, last = (int(v) for v in args.seeds.split(":"))
    rows = np.array([trial(s, args.pushes, args.cone) for s in range(first, last)])
    n = len(rows)
    print(f"seeds {first}:{last}, {args.pushes} pushes, cone {args.cone}")
    print(f"final region in both blocks: {rows[:, 2].sum()}/{n}")
    print(f"wrong block, largest-area part (the paper): {rows[:, 1].sum()}/{n}")
    print(f"wrong block, estimate_progressive: {rows[:, 0].sum()}/{n}")
    print(f"  of them, final region one part (through the bar): {(rows[:, 0] & rows[:, 3]).sum()}")


if __name__ == "__main__":
    main()
