"""ggins_log: read ggins LCM event logs (run.lcmlog) into NumPy arrays.

    import ggins_log
    log = ggins_log.read("out/run/run.lcmlog")
    nav = log["GGINS_NAV"]            # a Channel: one NumPy array per field
    nav["r_i"].shape                  # (n_messages, 3)
    nav.event_utime                   # event time stamps of the log, microseconds

Messages are decoded with the Python classes that lcm-gen generates at build time from
lcmtypes/*.lcm (package ``ggins``, build/lcmtypes/python): each message is matched to
its type by the 8-byte fingerprint it starts with, so every channel of every type the
build knows is read, with no list of channels here. Events whose fingerprint matches no
type are counted in ``Log.unknown``, messages of a known type that do not decode in
``Log.undecodable``; a log cut short is read up to its last complete event and says where
it ends in ``Log.truncated_at``. ``Log.problems()`` lists all of these in words (empty
for a whole log).
"""
from .eventlog import CorruptLog, Event, read_events, write_events, SYNC
from .arrays import Channel, Log, read, load_types, batch_items, item_channel
from .retime import retime

__all__ = ["CorruptLog", "Event", "read_events", "write_events", "SYNC", "Channel", "Log", "read", "load_types", "batch_items", "item_channel", "retime"]
