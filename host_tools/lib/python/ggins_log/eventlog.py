"""The LCM event-log file format (lcm/eventlog.c): each event is

    uint32 sync word 0xEDA1DA01, int64 event number, int64 timestamp (microseconds),
    int32 channel length, int32 data length, channel bytes, data bytes

all big-endian. Only `struct` is needed."""
import os
import struct
from dataclasses import dataclass
from typing import BinaryIO, Iterable, Iterator, Optional

SYNC = 0xEDA1DA01
_HEADER = struct.Struct(">IqqII")


@dataclass
class Event:
    eventnum: int
    timestamp: int  # microseconds
    channel: str
    data: bytes


class CorruptLog(ValueError):
    """A log whose bytes are not a sequence of LCM events (a broken sync word, a length
    beyond the file's end)."""


# An event's channel name is at most 256 bytes in LCM (LCM_MAX_CHANNEL_NAME_LENGTH 63 for
# UDP multicast; the log format allows 256); its data at most the file.
MAX_CHANNEL_LEN = 256


def read_events(f: BinaryIO, status: Optional[dict] = None) -> Iterator[Event]:
    """Events of an open binary log, in file order. A broken sync word or an impossible
    length is a CorruptLog error. A log cut short (a partial last event: the run's
    process stopped while writing) ends the iteration; the byte offset of the cut is
    then in status["truncated_at"] (None when the log ends on an event boundary; an event
    whose lengths run past the end of the file counts as the cut), and
    status["events"] counts the events read."""
    if status is None:
        status = {}
    status["truncated_at"] = None
    status["events"] = 0
    try:
        size = os.fstat(f.fileno()).st_size
    except (AttributeError, OSError, ValueError):  # not a file: no bound but the lengths' own
        size = None
    while True:
        at = f.tell()
        head = f.read(_HEADER.size)
        if len(head) == 0:
            return
        if len(head) < _HEADER.size:
            status["truncated_at"] = at
            return
        sync, num, ts, clen, dlen = _HEADER.unpack(head)
        if sync != SYNC:
            raise CorruptLog(f"bad sync word 0x{sync:08X} at offset {at} (want 0x{SYNC:08X})")
        if clen > MAX_CHANNEL_LEN or dlen >= 0x80000000:
            raise CorruptLog(f"event {num} at offset {at}: channel length {clen}, data length {dlen} "
                             f"(allowed: channel <= {MAX_CHANNEL_LEN} bytes, data < 2 GiB)")
        if size is not None and at + _HEADER.size + clen + dlen > size:  # never allocate past the end
            status["truncated_at"] = at
            return
        ch = f.read(clen)
        data = f.read(dlen)
        if len(ch) < clen or len(data) < dlen:
            status["truncated_at"] = at
            return
        status["events"] += 1
        yield Event(num, ts, ch.decode("utf-8", "replace"), data)


def write_events(f: BinaryIO, events: Iterable[Event]) -> int:
    """Write events in the same format; returns the count."""
    n = 0
    for e in events:
        ch = e.channel.encode("utf-8")
        f.write(_HEADER.pack(SYNC, e.eventnum, e.timestamp, len(ch), len(e.data)))
        f.write(ch)
        f.write(e.data)
        n += 1
    return n
