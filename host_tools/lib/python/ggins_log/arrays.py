"""Decode a log into one NumPy array per channel and field."""
import importlib
import inspect
import os
import sys
from typing import Dict, Optional

import numpy as np

from .eventlog import read_events

_HERE = os.path.dirname(os.path.abspath(__file__))
# build/lcmtypes/python of the repository this package sits in (host_tools/lib/python/ggins_log)
_DEFAULT_TYPES = os.path.normpath(os.path.join(_HERE, "..", "..", "..", "build", "lcmtypes", "python"))


def load_types(path: Optional[str] = None) -> Dict[bytes, type]:
    """Map fingerprint -> class over every type of the generated package ``ggins``.
    The package is looked for in `path`, then $GGINS_LCMTYPES_PYTHON, then sys.path,
    then the build folder of this repository."""
    for p in (path, os.environ.get("GGINS_LCMTYPES_PYTHON")):
        if p and p not in sys.path:
            sys.path.insert(0, p)
    try:
        pkg = importlib.import_module("ggins")
    except ImportError:
        sys.path.append(_DEFAULT_TYPES)
        pkg = importlib.import_module("ggins")
    types = {}
    for _, cls in inspect.getmembers(pkg, inspect.isclass):
        if hasattr(cls, "_get_packed_fingerprint") and hasattr(cls, "decode"):
            types[cls._get_packed_fingerprint()] = cls
    if not types:
        raise ImportError(f"no LCM types in the package ggins at {pkg.__file__}")
    return types


def _flatten(msg, prefix=""):
    """(name, value) pairs of a decoded message: nested structs as dotted names,
    fixed arrays as nested lists, byte arrays as bytes."""
    for name in msg.__slots__:
        v = getattr(msg, name)
        if hasattr(v, "__slots__"):
            yield from _flatten(v, prefix + name + ".")
        elif isinstance(v, (list, tuple)) and v and hasattr(v[0], "__slots__"):
            for i, x in enumerate(v):
                yield from _flatten(x, f"{prefix}{name}[{i}].")
        else:
            yield prefix + name, v


def batch_items(msg):
    """The inner messages of a batch message (a ``*_batch_t``: frames or outputs several to
    a message, as the batched lockstep sends them), or None for any other message."""
    if not type(msg).__name__.endswith("_batch_t"):
        return None
    for name in msg.__slots__:
        v = getattr(msg, name)
        if isinstance(v, (list, tuple)) and (not v or hasattr(v[0], "__slots__")) and name != "mac":
            return list(v)
    return None


def item_channel(batch_channel):
    """The channel of single messages whose items a batch channel carries: the runners
    name a batch channel by the plural of its single channel (GGINS_FRAMES carries
    GGINS_FRAME's frames, GGINS_NAVS GGINS_NAV's outputs, GGINS_NAV3DS GGINS_NAV3D's)."""
    return batch_channel[:-1] if batch_channel.endswith("S") else batch_channel


def _to_array(values):
    first = values[0]
    if isinstance(first, (bytes, bytearray)):
        n = max(len(v) for v in values)
        if all(len(v) == n for v in values):
            return np.frombuffer(b"".join(values), dtype=np.uint8).reshape(len(values), n)
        return np.array(values, dtype=object)
    if isinstance(first, str):
        return np.array(values, dtype=object)
    try:
        return np.asarray(values)
    except ValueError:  # variable-length arrays
        return np.array(values, dtype=object)


class Channel:
    """The messages of one channel: ``ch[field]`` is an array with one row per message
    (fields of nested structs as "outer.inner"); ``event_utime`` and ``eventnum`` come
    from the log's event headers; ``type`` is the generated class."""

    def __init__(self, name, cls, messages, event_utime, eventnum):
        self.name = name
        self.type = cls
        self.messages = messages
        self.event_utime = np.asarray(event_utime, dtype=np.int64)
        self.eventnum = np.asarray(eventnum, dtype=np.int64)
        self._fields = None

    def _build(self):
        cols = {}
        for m in self.messages:
            for k, v in _flatten(m):
                cols.setdefault(k, []).append(v)
        self._fields = {k: _to_array(v) for k, v in cols.items()}

    @property
    def fields(self):
        if self._fields is None:
            self._build()
        return self._fields

    def __getitem__(self, k):
        return self.fields[k]

    def keys(self):
        return self.fields.keys()

    def __len__(self):
        return len(self.messages)

    def __repr__(self):
        return f"Channel({self.name!r}, {self.type.__name__}, {len(self)} messages)"


class Log(dict):
    """Channel name -> Channel; ``unknown`` counts events per channel whose fingerprint
    matches no generated type, ``undecodable`` those of a known type that do not decode
    (truncated or corrupt messages); ``truncated_at`` is the byte offset where a log cut
    short ends (None for a complete log), ``events`` the number of events read."""

    def __init__(self):
        super().__init__()
        self.unknown = {}
        self.undecodable = {}
        self.truncated_at = None
        self.events = 0

    def problems(self):
        """What makes the log incomplete or corrupt, one line each (empty: none)."""
        out = []
        if self.events == 0:
            out.append("no LCM events")
        if self.truncated_at is not None:
            out.append(f"cut short: a partial event at byte {self.truncated_at} (the run stopped while writing?)")
        for ch, n in sorted(self.undecodable.items()):
            out.append(f"{n} message(s) on {ch} of a known type that do not decode")
        return out


def read(path, types=None, channels=None, unbatch=True) -> Log:
    """Read an LCM log into a Log. types: a fingerprint -> class map (load_types());
    channels: only these channel names (default all; batch channels are selected by
    the name of the channel their items go to). unbatch: the items of batch messages
    are listed, in log order, under the channel of single messages they stand for
    (item_channel), beside any single messages sent there (real-time runs send one
    frame per message); the event stamp and number of an item are its batch's."""
    types = types or load_types()
    acc = {}
    log = Log()
    status = {}
    with open(path, "rb") as f:
        for e in read_events(f, status):
            if channels is not None and e.channel not in channels and (
                    not unbatch or item_channel(e.channel) not in channels):
                continue
            cls = types.get(e.data[:8])
            msg = None
            if cls is not None:
                try:
                    msg = cls.decode(e.data)
                except Exception:  # a message of a known type that does not decode (truncated, corrupt)
                    log.undecodable[e.channel] = log.undecodable.get(e.channel, 0) + 1
                    continue
            if msg is None:
                log.unknown[e.channel] = log.unknown.get(e.channel, 0) + 1
                continue
            items = batch_items(msg) if unbatch else None
            if items is None:
                items, ch = [msg], e.channel
            else:
                ch = item_channel(e.channel)
                if channels is not None and ch not in channels:
                    continue
            for m in items:
                a = acc.setdefault((ch, type(m)), ([], [], []))
                a[0].append(m)
                a[1].append(e.timestamp)
                a[2].append(e.eventnum)
    log.truncated_at = status["truncated_at"]
    log.events = status["events"]
    for (ch, cls), (msgs, ts, num) in acc.items():
        name = ch if ch not in log else f"{ch}:{cls.__name__}"  # two types on one channel
        log[name] = Channel(name, cls, msgs, ts, num)
    return log
