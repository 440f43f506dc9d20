// A bounded reader of LCM event logs (the format lcm_eventlog_write_event
// writes): a sequence of events, each
//
//   sync word   uint32  0xEDA1DA01
//   event number int64  0, 1, 2, ... (lcm_eventlog numbers the events it writes)
//   timestamp   int64   microseconds
//   channel len int32
//   data len    int32
//   channel     channel-len bytes (no NUL)
//   data        data-len bytes
//
// all integers big-endian. Unlike liblcm's reader (which trusts the lengths and
// skips forward to the next sync word after a bad one), every header is checked
// before anything is read from it: the sync word, a channel length within
// 1..kMaxChannel of printable ASCII, a data length within 0..max_data and
// within the bytes left in the file. The first violation stops the reading;
// what was read before it is kept, and the violation is reported with its byte
// offset, so a truncated or corrupt log is named as such instead of read as a
// shorter valid one. Event numbers must run 0, 1, 2, ...: a break (events
// removed, inserted or reordered) is reported too, and reading goes on.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ggins::replay {

struct LogEvent {
  int64_t eventnum = 0, timestamp = 0;
  uint64_t offset = 0;  // byte offset of the event's sync word
  std::string_view channel;  // into LcmLog::bytes
  const uint8_t* data = nullptr;  // into LcmLog::bytes
  int32_t datalen = 0;
};

struct LcmLog {
  LcmLog() = default;
  LcmLog(LcmLog&&) = default;  // the events point into bytes: moved with them, never copied
  LcmLog& operator=(LcmLog&&) = default;
  LcmLog(const LcmLog&) = delete;
  LcmLog& operator=(const LcmLog&) = delete;
  enum class Error {
    kNone,
    kOpen,       // the file cannot be opened or read
    kNotLog,     // no sync word at byte 0: not an LCM event log
    kSync,       // a later event does not start with the sync word
    kHeader,     // impossible channel or data length, or a channel that is not printable ASCII
    kTruncated,  // the last event runs past the end of the file
  };
  std::vector<uint8_t> bytes;  // the whole file
  std::vector<LogEvent> events;
  Error error = Error::kNone;  // the framing error that stopped the reading
  std::string message;         // what is wrong, where (empty when error == kNone)
  uint64_t error_offset = 0;   // byte offset of the offending event header
  int64_t numbering_breaks = 0;   // events whose number is not the previous + 1 (the first: 0)
  std::string numbering_message;  // the first of them
};

constexpr int32_t kMaxChannel = 256;               // bytes of a channel name
constexpr int32_t kDefaultMaxData = 64 << 20;      // bytes of one message: far above any ggins message
constexpr uint32_t kSyncWord = 0xEDA1DA01u;
constexpr int kHeaderBytes = 4 + 8 + 8 + 4 + 4;

// Read and check the log at `path` (see above). Never reads beyond the file.
LcmLog read_lcm_log(const std::string& path, int32_t max_data = kDefaultMaxData);

// The same on bytes in memory (the tests' entry point; `path` only names them).
LcmLog parse_lcm_log(std::vector<uint8_t> bytes, int32_t max_data = kDefaultMaxData);

const char* error_name(LcmLog::Error e);

}  // namespace ggins::replay
