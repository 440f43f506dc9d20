// libFuzzer harness: the bounded LCM event log reader of ggins replay
// (host_tools/apps/replay/lcmlog_reader.cpp) on arbitrary bytes.
//
// Invariants (abort = a finding), besides no crash and no sanitizer report:
//  - every event read lies inside the input: header, channel and data;
//  - events are contiguous from byte 0 (each starts where the one before ended);
//  - the reading stops at the end of the input exactly, or an error is reported
//    at the offset where the last event read ended;
//  - channel lengths 1..kMaxChannel, data lengths 0..max_data.
// Seeds: any LCM log (e.g. a short run's run.lcmlog cut to a few KB).
#include <cstdio>
#include <cstdlib>

#include "lcmlog_reader.hpp"

using namespace ggins::replay;

#define FUZZ_FAIL(msg)                                      \
  do {                                                      \
    std::fprintf(stderr, "fuzz_lcmlog: %s\n", msg);         \
    std::abort();                                           \
  } while (0)

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const int32_t max_data = 4096;  // small cap: the length checks are reached often
  const LcmLog log = parse_lcm_log(std::vector<uint8_t>(data, data + size), max_data);
  const uint8_t* base = log.bytes.data();
  uint64_t end = 0;
  for (const LogEvent& e : log.events) {
    if (e.offset != end) FUZZ_FAIL("events not contiguous");
    const int32_t clen = static_cast<int32_t>(e.channel.size());
    if (clen < 1 || clen > kMaxChannel) FUZZ_FAIL("channel length out of range");
    if (e.datalen < 0 || e.datalen > max_data) FUZZ_FAIL("data length out of range");
    const uint64_t stop = e.offset + static_cast<uint64_t>(kHeaderBytes) + static_cast<uint64_t>(clen) +
                          static_cast<uint64_t>(e.datalen);
    if (stop > size) FUZZ_FAIL("event beyond the input");
    if (e.data != base + e.offset + kHeaderBytes + clen) FUZZ_FAIL("data pointer not after the channel");
    end = stop;
  }
  if (log.error == LcmLog::Error::kNone) {
    if (end != size) FUZZ_FAIL("no error reported, input not consumed");
  } else {
    if (log.error_offset != end) FUZZ_FAIL("error not at the end of the last event read");
    if (log.message.empty()) FUZZ_FAIL("error without a message");
  }
  return 0;
}
