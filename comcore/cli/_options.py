"""Argument types shared by the subcommands: argparse errors that name the option."""

from __future__ import annotations

import argparse

__all__ = ["box", "non_negative_int", "positive_int", "threshold"]


def _int(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None


def positive_int(text: str) -> int:
    """An integer >= 1 (argparse type).

    Examples
    --------
    >>> positive_int("3")
    3
    >>> positive_int("-1")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: expected a positive integer, got -1
    """
    value = _int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text}")
    return value


def non_negative_int(text: str) -> int:
    """An integer >= 0 (argparse type).

    Examples
    --------
    >>> non_negative_int("0")
    0
    """
    value = _int(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected an integer >= 0, got {text}")
    return value


def threshold(text: str) -> str | float:
    """``auto``, ``otsu`` or a grey level (argparse type of ``--threshold``).

    Examples
    --------
    >>> threshold("otsu"), threshold("120")
    ('otsu', 120.0)
    >>> threshold("high")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: expected auto, otsu or a grey level (a number), got 'high'
    """
    if text in ("auto", "otsu"):
        return text
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if value != value or value in (float("inf"), float("-inf")):
        raise argparse.ArgumentTypeError(
            f"expected auto, otsu or a grey level (a number), got {text!r}"
        )
    return value


def box(text: str) -> tuple[int, int, int, int]:
    """``x0,y0,x1,y1`` in pixels: a box (argparse type of ``--roi``).

    Examples
    --------
    >>> box("100,50,400,300")
    (100, 50, 400, 300)
    >>> box("100,50,400")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: expected x0,y0,x1,y1 (four integers, pixels), got '100,50,400'
    """
    try:
        values = tuple(int(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != 4:
        raise argparse.ArgumentTypeError(
            f"expected x0,y0,x1,y1 (four integers, pixels), got {text!r}"
        )
    return values
