"""Opening a bag with rosbags' ``AnyReader``, its errors as ValueError (``bag``, its images)."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["_Open", "_listing", "_reader", "_topic_type"]


def _reader(path):
    """An unopened ``rosbags.highlevel.AnyReader`` of ``path`` (ImportError without rosbags)."""
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError as e:
        raise ImportError("reading ROS bags needs rosbags: pip install comcore[ros]") from e
    path = Path(os.fspath(path))
    if not path.exists():
        raise ValueError(f"path: no such bag: {path}")
    try:
        return AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE))
    except Exception as e:  # rosbags raises its own error types (and OSError) for a bad path
        raise ValueError(f"path: cannot read {path} as a bag: {e}") from e


class _Open:
    """``with _Open(path) as reader``: the bag opened, its errors as ValueError."""

    def __init__(self, path):
        self.path = path
        self.reader = _reader(path)

    def __enter__(self):
        try:
            self.reader.open()
        except Exception as e:  # rosbags raises its own error types for a bad file
            raise ValueError(f"path: cannot read {os.fspath(self.path)} as a bag: {e}") from e
        return self.reader

    def __exit__(self, *exc):
        self.reader.close()


def _listing(topics: dict) -> str:
    return ", ".join(f"{t} ({info.msgtype})" for t, info in sorted(topics.items())) or "none"


def _topic_type(reader, path, topic: str, supported: tuple, kind: str) -> str:
    """The message type of ``topic`` in the open bag, if it is one of ``supported``.

    Otherwise a ValueError naming the topic: not in the bag (its topics listed), or
    holding another type (``kind`` says what was wanted, the supported types listed).
    """
    if topic not in reader.topics:
        raise ValueError(
            f"topic {topic!r} is not in {os.fspath(path)}; its topics: {_listing(reader.topics)}"
        )
    msgtype = reader.topics[topic].msgtype
    if msgtype not in supported:
        raise ValueError(
            f"topic {topic!r} holds {msgtype}, not {kind}; supported: {', '.join(supported)}"
        )
    return msgtype
