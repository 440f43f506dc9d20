"""A TOML writer for scenario tables (what tomllib reads back): tables, arrays of tables,
strings, booleans, integers, floats (repr: round-trips exactly), arrays of scalars."""
import json
import math


def _scalar(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        r = repr(v)
        return r if any(c in r for c in ".eEn") else r + ".0"
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_scalar(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join("%s = %s" % (_key(k), _scalar(x)) for k, x in v.items()) + "}"
    raise TypeError("cannot write %r as TOML" % (v,))


def _key(k):
    if k and all(c.isalnum() or c in "_-" for c in k):
        return k
    return json.dumps(k)


def _is_table_array(v):
    return isinstance(v, list) and v and all(isinstance(x, dict) for x in v)


def _emit(d, path, lines):
    plain = [(k, v) for k, v in d.items() if not isinstance(v, dict) and not _is_table_array(v)]
    for k, v in plain:
        lines.append("%s = %s" % (_key(k), _scalar(v)))
    for k, v in d.items():
        if isinstance(v, dict):
            p = path + [_key(k)]
            lines.append("")
            lines.append("[%s]" % ".".join(p))
            _emit(v, p, lines)
        elif _is_table_array(v):
            p = path + [_key(k)]
            for item in v:
                lines.append("")
                lines.append("[[%s]]" % ".".join(p))
                _emit(item, p, lines)


def dumps(d):
    lines = []
    _emit(d, [], lines)
    return "\n".join(lines).lstrip("\n") + "\n"


def set_dotted(d, key, value):
    """d["a"]["b"] = value for key "a.b", creating tables as needed."""
    parts = key.split(".")
    for p in parts[:-1]:
        nxt = d.setdefault(p, {})
        if not isinstance(nxt, dict):
            raise ValueError("scenario key %s: %s is not a table" % (key, p))
        d = nxt
    d[parts[-1]] = value
