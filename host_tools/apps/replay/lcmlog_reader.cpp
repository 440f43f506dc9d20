// Bounded LCM event log reader: see lcmlog_reader.hpp.
#include "lcmlog_reader.hpp"

#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <fstream>
#include <iterator>

namespace ggins::replay {

namespace {

uint32_t be32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}
uint64_t be64(const uint8_t* p) { return (uint64_t{be32(p)} << 32) | uint64_t{be32(p + 4)}; }

std::string fmt(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char* f, ...) {
  char s[512];
  va_list ap;
  va_start(ap, f);
  std::vsnprintf(s, sizeof s, f, ap);
  va_end(ap);
  return s;
}

}  // namespace

const char* error_name(LcmLog::Error e) {
  switch (e) {
    case LcmLog::Error::kNone: return "none";
    case LcmLog::Error::kOpen: return "unreadable";
    case LcmLog::Error::kNotLog: return "not an LCM log";
    case LcmLog::Error::kSync: return "corrupt event header (sync word)";
    case LcmLog::Error::kHeader: return "corrupt event header (lengths)";
    case LcmLog::Error::kTruncated: return "truncated";
  }
  return "?";
}

LcmLog parse_lcm_log(std::vector<uint8_t> bytes, int32_t max_data) {
  LcmLog log;
  log.bytes = std::move(bytes);
  const uint8_t* const base = log.bytes.data();
  const uint64_t size = log.bytes.size();
  uint64_t pos = 0;
  int64_t expect = 0;  // next event number
  auto fail = [&](LcmLog::Error e, std::string m) {
    log.error = e;
    log.error_offset = pos;
    log.message = std::move(m);
  };
  // bounded: every pass consumes at least kHeaderBytes of the file
  while (pos < size) {
    const uint64_t left = size - pos;
    const size_t n_read = log.events.size();
    if (left < static_cast<uint64_t>(kHeaderBytes)) {
      fail(LcmLog::Error::kTruncated,
           fmt("truncated: %" PRIu64 " bytes at byte %" PRIu64 " after event %zu, fewer than an event header (%d)",
               left, pos, n_read, kHeaderBytes));
      break;
    }
    const uint8_t* h = base + pos;
    const uint32_t sync = be32(h);
    if (sync != kSyncWord) {
      fail(pos == 0 ? LcmLog::Error::kNotLog : LcmLog::Error::kSync,
           pos == 0 ? fmt("not an LCM event log: the first 4 bytes are 0x%08" PRIx32 ", not the sync word 0x%08" PRIx32,
                          sync, kSyncWord)
                    : fmt("corrupt event header at byte %" PRIu64 " (after %zu events): sync word 0x%08" PRIx32
                          ", not 0x%08" PRIx32,
                          pos, n_read, sync, kSyncWord));
      break;
    }
    const int64_t num = static_cast<int64_t>(be64(h + 4));
    const int64_t ts = static_cast<int64_t>(be64(h + 12));
    const int32_t clen = static_cast<int32_t>(be32(h + 20));
    const int32_t dlen = static_cast<int32_t>(be32(h + 24));
    if (clen < 1 || clen > kMaxChannel) {
      fail(LcmLog::Error::kHeader, fmt("corrupt event header at byte %" PRIu64 " (event number %" PRId64
                                       "): channel length %" PRId32 " (must be 1..%d)",
                                       pos, num, clen, kMaxChannel));
      break;
    }
    if (dlen < 0 || dlen > max_data) {
      fail(LcmLog::Error::kHeader, fmt("corrupt event header at byte %" PRIu64 " (event number %" PRId64
                                       "): data length %" PRId32 " (must be 0..%" PRId32 "; %" PRIu64
                                       " bytes left in the file)",
                                       pos, num, dlen, max_data, left));
      break;
    }
    const uint64_t need = static_cast<uint64_t>(kHeaderBytes) + static_cast<uint64_t>(clen) + static_cast<uint64_t>(dlen);
    if (need > left) {
      fail(LcmLog::Error::kTruncated,
           fmt("truncated: event number %" PRId64 " at byte %" PRIu64 " declares %" PRIu64
               " bytes (channel %" PRId32 ", data %" PRId32 "), the file has %" PRIu64 " left",
               num, pos, need, clen, dlen, left));
      break;
    }
    const uint8_t* ch = h + kHeaderBytes;
    bool printable = true;
    for (int32_t i = 0; i < clen; ++i) printable = printable && ch[i] >= 0x20 && ch[i] <= 0x7e;
    if (!printable) {
      fail(LcmLog::Error::kHeader, fmt("corrupt event header at byte %" PRIu64 " (event number %" PRId64
                                       "): the channel name (%" PRId32 " bytes) is not printable ASCII",
                                       pos, num, clen));
      break;
    }
    if (num != expect) {
      if (log.numbering_breaks == 0)
        log.numbering_message = fmt("event numbers break at byte %" PRIu64 ": event number %" PRId64
                                    " follows %" PRId64 " (events missing, added or reordered)",
                                    pos, num, expect - 1);
      ++log.numbering_breaks;
    }
    expect = num + 1;
    LogEvent e;
    e.eventnum = num;
    e.timestamp = ts;
    e.offset = pos;
    e.channel = std::string_view(reinterpret_cast<const char*>(ch), static_cast<size_t>(clen));
    e.data = ch + clen;
    e.datalen = dlen;
    log.events.push_back(std::move(e));
    pos += need;
  }
  return log;
}

LcmLog read_lcm_log(const std::string& path, int32_t max_data) {
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    LcmLog log;
    log.error = LcmLog::Error::kOpen;
    log.message = "cannot open " + path;
    return log;
  }
  std::vector<uint8_t> b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (f.bad()) {
    LcmLog log;
    log.error = LcmLog::Error::kOpen;
    log.message = "cannot read " + path;
    return log;
  }
  return parse_lcm_log(std::move(b), max_data);
}

}  // namespace ggins::replay
