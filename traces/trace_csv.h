#pragma once
// CSV form of the trace format (traces/FORMAT.md, "CSV form"): for small hand-written cases.
// Texture table as `# texture <id> <name> <source> <width> <height> [<storage>]` directives (and
// the sampler table as `# sampler <name> key=value ...`), then a
// header line naming the columns, then one fragment per line. Read line by line, never loaded
// whole.
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "blocks/base/fragment.h"
#include "traces/trace_file.h"

namespace texsim {

inline constexpr uint32_t kCsvRecordsPerChunk = 4096;
inline constexpr size_t kCsvMaxLineBytes = 65536;

class TraceCsvReader {
 public:
  // Opens `path` and reads the directives and the column header line; throws InputError.
  explicit TraceCsvReader(const std::string& path,
                          uint32_t records_per_chunk = kCsvRecordsPerChunk);
  ~TraceCsvReader();
  TraceCsvReader(const TraceCsvReader&) = delete;
  TraceCsvReader& operator=(const TraceCsvReader&) = delete;

  const TraceHeader& header() const { return header_; }
  size_t next_chunk(std::vector<Fragment>& out);  // 0 at end of file

 private:
  bool next_line(std::string_view& line);  // false at end of file
  struct Token {
    std::string text;
    size_t column;  // 1-based
  };
  void parse_directive(std::string_view line);
  std::vector<Token> directive_tokens(std::string_view line, size_t after) const;
  void parse_texture_directive(const std::vector<Token>& tokens, size_t i);
  void parse_sampler_directive(const std::vector<Token>& tokens, size_t i);
  void parse_columns(std::string_view line);
  void parse_record(std::string_view line, Fragment& f);
  [[noreturn]] void fail(size_t column, const std::string& what) const;

  std::string path_;
  TraceFilePtr file_;
  TraceHeader header_;
  uint32_t records_per_chunk_;
  std::vector<char> buf_;
  size_t buf_begin_ = 0, buf_end_ = 0;
  bool eof_ = false;
  uint64_t line_no_ = 0;
  std::string long_line_;  // a line that straddles the read buffer
  TextureIdSet ids_;
  std::set<std::string> sampler_names_;  // the sampler directives' names, each once
  // For each column, the index into trace_field_specs() or -1 for a skipped column.
  std::vector<int> column_field_;
  size_t required_columns_ = 0;
};

// Streaming CSV writer with the same contract as TraceWriter: temporary name, rename on
// close(), temporary removed if destroyed without close(). Values are written in the shortest
// form that reads back to the same double/float, so CSV <-> binary round trips are exact.
class TraceCsvWriter {
 public:
  TraceCsvWriter(const std::string& path, const TraceHeader& header);
  ~TraceCsvWriter();
  TraceCsvWriter(const TraceCsvWriter&) = delete;
  TraceCsvWriter& operator=(const TraceCsvWriter&) = delete;

  void write(const Fragment& f);
  void close();
  uint64_t records_written() const { return records_; }

 private:
  void put(std::string_view s);
  [[noreturn]] void fail(const std::string& what);

  std::string path_, temp_;
  TraceFilePtr file_;
  bool has_lod_bias_ = false;
  bool has_view_ = false;
  bool has_ops_ = false;
  TextureIdSet ids_;
  std::string line_;
  uint64_t records_ = 0;
  bool closed_ = false;
};

// The `# sampler <name> key=value ...` directive of a sampler table entry, every key written.
std::string csv_sampler_directive(const TraceSampler& s);
// Quotes a directive token when it is empty or holds whitespace, '"' or '\\'.
std::string csv_quote_token(std::string_view s);

}  // namespace texsim
