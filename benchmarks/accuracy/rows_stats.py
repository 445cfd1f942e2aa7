"""Head-to-head shares from a ``comcore bench`` result file, per friction class.

Run: ``python benchmarks/accuracy/rows_stats.py bench-out/full/results.jsonl
[--pair alg2:centroid ...]``.

For each pair ``A:B`` it matches the rows of the two estimators on the same
trial (object, friction, trial number) and prints, per friction class and for
all of them, the share of trials where A's error is strictly smaller than B's,
the share of ties and the number of matched trials. Rows with status
``"error"`` (an estimator that raised) are left out. Reads ``.jsonl`` or
``.parquet`` (``comcore.bench._io.read_rows``).
"""

from __future__ import annotations

import argparse

from comcore.bench._io import read_rows

DEFAULT_PAIRS = ("alg2:centroid", "alg1:centroid")


def _pair(text: str) -> tuple[str, str]:
    a, sep, b = text.partition(":")
    if not (sep and a and b):
        raise argparse.ArgumentTypeError(f"a pair is A:B (e.g. alg2:centroid), got {text!r}")
    return a, b


def beats(rows, a: str, b: str) -> dict[str, dict]:
    """Per friction class (and ``"all"``): trials where ``a`` beats ``b``.

    Parameters
    ----------
    rows : iterable of dict
        Result rows (``comcore.bench.ROW_FIELDS``).
    a, b : str
        Estimator labels as written in the rows.

    Returns
    -------
    dict
        ``{friction: {"n": matched trials, "wins": a's error < b's, "ties": equal}}``.

    Raises
    ------
    ValueError
        If one of the estimators has no row.

    Examples
    --------
    >>> rows = [{"object": "O", "friction": "low", "trial": t, "estimator": e,
    ...          "status": "ok", "error_cm": x}
    ...         for t, (xa, xb) in enumerate([(1, 2), (3, 2), (1, 1)])
    ...         for e, x in (("a", xa), ("b", xb))]
    >>> beats(rows, "a", "b")["low"]
    {'n': 3, 'wins': 1, 'ties': 1}
    """
    errors: dict[str, dict] = {a: {}, b: {}}
    for row in rows:
        if row["estimator"] in errors and row["status"] != "error":
            key = (row["object"], row["friction"], row["trial"])
            errors[row["estimator"]][key] = float(row["error_cm"])
    for name in (a, b):
        if not errors[name]:
            raise ValueError(f"estimator {name!r} has no usable row in the results")
    counts: dict[str, dict] = {}
    for key in sorted(errors[a].keys() & errors[b].keys()):
        ea, eb = errors[a][key], errors[b][key]
        for group in (key[1], "all"):
            c = counts.setdefault(group, {"n": 0, "wins": 0, "ties": 0})
            c["n"] += 1
            c["wins"] += ea < eb
            c["ties"] += ea == eb
    return counts


def main(argv=None) -> None:
    """Print the shares for each ``--pair``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", help="results.jsonl or results.parquet of comcore bench")
    parser.add_argument(
        "--pair",
        type=_pair,
        action="append",
        metavar="A:B",
        help=f"estimators to compare (default {' '.join(DEFAULT_PAIRS)})",
    )
    args = parser.parse_args(argv)
    try:
        rows = read_rows(args.results)
    except (OSError, ValueError) as e:
        parser.error(f"cannot read {args.results}: {e}")
    for a, b in args.pair or [_pair(p) for p in DEFAULT_PAIRS]:
        try:
            counts = beats(rows, a, b)
        except ValueError as e:
            parser.error(str(e))
        order = sorted(counts, key=lambda g: (g == "all", {"low": 0, "high": 1}.get(g, 2), g))
        for group, c in ((g, counts[g]) for g in order):
            print(
                f"{a} beats {b} ({group}): {100 * c['wins'] / c['n']:.1f} % of {c['n']} trials "
                f"(ties {100 * c['ties'] / c['n']:.1f} %)"
            )


if __name__ == "__main__":
    main()
