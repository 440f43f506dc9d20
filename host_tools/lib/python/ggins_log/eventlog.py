"""The LCM event-log file format (lcm/eventlog.c): each event is

    uint32 sync word 0xEDA1DA01, int64 event number, int64 timestamp (microseconds),
    int32 channel length, int32 data length, channel bytes, data bytes

all big-endian. Only `struct` is needed."""
import struct
from dataclasses import dataclass
from typing import BinaryIO, Iterable, Iterator

SYNC = 0xEDA1DA01
_HEADER = struct.Struct(">IqqII")


@dataclass
class Event:
    eventnum: int
    timestamp: int  # microseconds
    channel: str
    data: bytes


def read_events(f: BinaryIO) -> Iterator[Event]:
    """Events of an open binary log, in file order. A truncated last event (a log cut
    short) ends the iteration; a broken sync word is an error."""
    while True:
        head = f.read(_HEADER.size)
        if len(head) < _HEADER.size:
            return
        sync, num, ts, clen, dlen = _HEADER.unpack(head)
        if sync != SYNC:
            raise ValueError(f"bad sync word 0x{sync:08X} at offset {f.tell() - _HEADER.size} (want 0x{SYNC:08X})")
        ch = f.read(clen)
        data = f.read(dlen)
        if len(ch) < clen or len(data) < dlen:
            return
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
