"""Rewrite a log's event time stamps to flight time, so that lcm-logplayer replays a
lockstep run (whose events carry the wall times of a run much faster than real time) at
1x flight time.

A message is on the flight clock when its type has a scalar field ``utime`` whose value is
more than a day away from the wall-clock time stamp of its event (a sensor frame, a truth
sample, a navigation output: ``utime`` is the sample time of the flight, from 0); a
``utime`` within a day of the event's stamp is a wall clock (configuration, control and
status messages). A flight-clock event gets the time stamp t0 + (utime - utime0), where
t0 is the first event's original stamp and utime0 the first flight-clock utime. Other
events keep their place in the file and take the stamp of the event before them, so the
stamps never decrease. The rule reads only the messages, never a list of channels or
types, so types added to lcmtypes/ are retimed by the same rule."""
from .eventlog import Event, read_events, write_events
from .arrays import batch_items, load_types


WALL_CLOCK_WINDOW_US = 86400 * 10**6  # a utime this close to its event's stamp is a wall clock


def flight_utime(msg, event_timestamp):
    """The flight time of a decoded message, microseconds, or None if it has none
    (no scalar utime, or a utime on the wall clock)."""
    items = batch_items(msg)
    if items:  # a batch: the flight time of its last item (a batch exists once its last item does)
        return flight_utime(items[-1], event_timestamp)
    if "utime" not in getattr(msg, "__slots__", ()):
        return None
    u = getattr(msg, "utime")
    if not isinstance(u, int) or abs(u - event_timestamp) <= WALL_CLOCK_WINDOW_US:
        return None
    return u


def retime(src, dst, types=None, speed=1.0):
    """Copy the log src to dst with flight-time event stamps (speed: 2 replays twice as
    fast). Returns (events, events on the flight clock, offset where src is cut short or
    None): the events of a log cut short are copied up to the cut."""
    types = types or load_types()
    status = {}
    with open(src, "rb") as f:
        events = list(read_events(f, status))
    if not events:
        raise ValueError(f"{src}: no events")
    t0 = events[0].timestamp
    u0 = None
    for e in events:
        cls = types.get(e.data[:8])
        if cls is not None:
            try:
                u0 = flight_utime(cls.decode(e.data), e.timestamp)
            except Exception:
                u0 = None
            if u0 is not None:
                break
    if u0 is None:
        raise ValueError(f"{src}: no message on the flight clock (a utime more than a day from its event stamp)")
    out, prev, n_flight = [], t0, 0
    for e in events:
        ts = None
        cls = types.get(e.data[:8])
        if cls is not None:
            try:
                u = flight_utime(cls.decode(e.data), e.timestamp)
            except Exception:
                u = None
            if u is not None:
                ts = t0 + int(round((u - u0) / speed))
                n_flight += 1
        ts = prev if ts is None else max(prev, ts)
        out.append(Event(e.eventnum, ts, e.channel, e.data))
        prev = ts
    with open(dst, "wb") as f:
        write_events(f, out)
    return len(out), n_flight, status["truncated_at"]
