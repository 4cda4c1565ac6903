#include "app/config/trajectory_file.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "app/config/bus_config.hpp"

namespace dxlemu::app {
namespace {

using model::JointUnit;
using model::Trajectory;
using model::TrajectoryColumn;

/// What spreadsheet programs put before the first byte of a UTF-8 CSV.
constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
/// The spellings of the time column (CSV) or key (JSON lines).
constexpr std::array<std::string_view, 3> kTimeNames{"time", "time_s", "t"};
/// How much of a cell or key a message quotes: a hostile file's megabyte cell stays out of it.
constexpr std::size_t kMaxQuoted = 40;
/// How much of nlohmann-json's description of a syntax error a message keeps (it ends with what
/// it last read, which can be long).
constexpr std::size_t kMaxDetail = 120;
/// Why a file with too many joint columns is refused.
const std::string kTooManyJoints = "more than " + std::to_string(kMaxTrajectoryColumns) +
                                   " joints, the most a trajectory may have";
/// The pointer of an error about the whole text (no header, no first object).
constexpr std::string_view kEndOfFile = "end of file";

/// `value` in the shortest form that reads back the same ("1.5", "1e-06").
std::string number_text(double value) {
  std::array<char, 32> digits{};
  const auto end = std::to_chars(digits.begin(), digits.end(), value).ptr;
  return {digits.begin(), end};
}

/// `text` for a message: at most `limit` characters (then "..."), bytes that are not printable
/// ASCII shown as '?'.
std::string printable(std::string_view text, std::size_t limit) {
  std::string out;
  for (const char c : text.substr(0, limit)) {
    out += c >= ' ' && c <= '~' ? c : '?';
  }
  return text.size() > limit ? out + "..." : out;
}

/// `text` in double quotes for a message, shortened as printable() does to kMaxQuoted.
std::string in_quotes(std::string_view text) {
  return "\"" + printable(text, kMaxQuoted) + "\"";
}

std::string_view trim(std::string_view text) {
  constexpr std::string_view kSpace = " \t\r";
  const auto first = text.find_first_not_of(kSpace);
  if (first == std::string_view::npos) {
    return {};
  }
  return text.substr(first, text.find_last_not_of(kSpace) - first + 1);
}

bool is_time_name(std::string_view name) {
  return std::find(kTimeNames.begin(), kTimeNames.end(), name) != kTimeNames.end();
}

/// A joint name: letters, digits, '_', '-', '.' (a servo ID is digits, so one too).
bool is_joint_name(std::string_view name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
}

/// A finite number written as the whole of `text` (already trimmed): what strtod reads, with an
/// optional '+' but no hexadecimal, infinity or NaN and nothing after it.
std::optional<double> parse_number(std::string_view text) {
  if (text.starts_with('+')) {
    text.remove_prefix(1);
    if (text.starts_with('-') || text.starts_with('+')) {
      return std::nullopt;
    }
  }
  double value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

/// The lines of a text, numbered from 1, without the byte order mark and without the '\r' of a
/// CRLF line end.
class Lines {
 public:
  explicit Lines(std::string_view text) : rest_(text) {
    if (rest_.starts_with(kByteOrderMark)) {
      rest_.remove_prefix(kByteOrderMark.size());
    }
  }

  /// The next line that is neither blank nor a comment ('#' first), and its number; false at the
  /// end of the text.
  bool next(std::string_view& line, std::size_t& number) {
    while (!done_) {
      const auto end = rest_.find('\n');
      line = rest_.substr(0, end);
      if (end == std::string_view::npos) {
        done_ = true;
      } else {
        rest_.remove_prefix(end + 1);
      }
      if (line.ends_with('\r')) {
        line.remove_suffix(1);
      }
      number = ++number_;
      const std::string_view content = trim(line);
      if (!content.empty() && !content.starts_with('#')) {
        return true;
      }
    }
    return false;
  }

 private:
  std::string_view rest_;
  std::size_t number_ = 0;
  bool done_ = false;
};

/// The checks and the keyframes both formats share: columns, times, values, limits, and the
/// message of every refusal.
class TrajectoryBuilder {
 public:
  explicit TrajectoryBuilder(const std::string& origin) : origin_(origin) {}

  [[noreturn]] void fail(std::size_t line, const std::string& reason) const {
    throw ConfigError(origin_, "line " + std::to_string(line), reason);
  }
  [[noreturn]] void fail_at_end(const std::string& reason) const {
    throw ConfigError(origin_, std::string(kEndOfFile), reason);
  }

  /// Adds the column written `spec` (`NAME`, `NAME:deg`, `NAME:raw`), `where` naming it in
  /// messages (`column 3 "gripper:raw"`).
  void add_column(std::string_view spec, std::size_t line, const std::string& where) {
    if (columns_.size() == kMaxTrajectoryColumns) {
      fail(line, kTooManyJoints);
    }
    // Spaces around the name and the unit are the writer's layout, not part of either.
    const auto colon = spec.find(':');
    const std::string_view name = trim(spec.substr(0, colon));
    JointUnit unit = JointUnit::Degrees;
    if (colon != std::string_view::npos) {
      const std::string_view suffix = trim(spec.substr(colon + 1));
      if (suffix == "raw") {
        unit = JointUnit::Raw;
      } else if (suffix != "deg") {
        fail(line, where + ": unknown unit " + in_quotes(suffix) + " (write NAME:deg or NAME:raw)");
      }
    }
    if (name.empty()) {
      fail(line, where + ": no joint name");
    }
    if (!is_joint_name(name)) {
      fail(line, where + ": " + in_quotes(name) +
                     " is neither a joint name (letters, digits, _, - and .) nor a servo ID");
    }
    if (is_time_name(name)) {
      fail(line, where + ": " + in_quotes(name) + " names the time, which comes once");
    }
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      if (columns_[c].joint == name) {
        fail(line, where + ": joint " + std::string(name) + " already has " + wheres_[c]);
      }
    }
    columns_.push_back({std::string(name), unit});
    wheres_.push_back(where);
  }

  std::size_t column_count() const { return columns_.size(); }

  /// The value `text` (trimmed) of column `c` on `line`.
  double value(std::string_view text, std::size_t c, std::size_t line) const {
    const auto value = parse_number(text);
    if (!value) {
      fail(line, wheres_[c] + ": " + in_quotes(text) + " is not a finite number");
    }
    return checked_value(*value, c, line);
  }

  /// `value` of column `c` on `line`, refused when it is too large for a trajectory.
  double checked_value(double value, std::size_t c, std::size_t line) const {
    if (!(std::abs(value) <= Trajectory::kMaxMagnitude)) {
      fail(line, wheres_[c] + ": " + number_text(value) + " is larger in magnitude than " +
                     number_text(Trajectory::kMaxMagnitude) +
                     ", the most a trajectory value may be");
    }
    return value;
  }

  /// The time `text` (trimmed) on `line`.
  double time(std::string_view text, std::size_t line) const {
    const auto value = parse_number(text);
    if (!value) {
      fail(line, "time " + in_quotes(text) + " is not a finite number");
    }
    return *value;
  }

  /// Starts the row of `line` at `time_s` (checked against the previous row's); its values follow
  /// with push_value().
  void start_row(std::size_t line, double time_s) {
    if (times_s_.size() == max_rows()) {
      fail(line, "more than " + std::to_string(max_rows()) +
                     " keyframes: a trajectory may have at most " +
                     std::to_string(kMaxTrajectoryRows) + " keyframes and " +
                     std::to_string(kMaxTrajectoryValues) + " values (keyframes times joints)");
    }
    // Built only for a refusal: this runs once per keyframe.
    const auto time = [&] { return "time " + number_text(time_s) + " s"; };
    if (times_s_.empty()) {
      if (time_s < 0) {
        fail(line, time() + " is negative: a trajectory starts at 0 s");
      }
    } else {
      const double previous = times_s_.back();
      if (!(time_s > previous)) {
        fail(line, time() + " is not after the previous row's " + number_text(previous) + " s");
      }
      if (time_s - previous < Trajectory::kMinStepS) {
        fail(line, time() + " is less than " + number_text(Trajectory::kMinStepS) +
                       " s after the previous row's " + number_text(previous) + " s");
      }
    }
    if (time_s > Trajectory::kMaxTimeS) {
      fail(line, time() + " is later than " + number_text(Trajectory::kMaxTimeS) +
                     " s, the latest a keyframe may be");
    }
    times_s_.push_back(time_s);
    lines_.push_back(line);
    rows_.emplace_back().reserve(columns_.size());
  }

  void push_value(double value) { rows_.back().push_back(value); }

  /// The trajectory; `columns_line` is where the columns were named.
  Trajectory build(std::size_t columns_line) && {
    if (times_s_.empty()) {
      fail(columns_line, "no keyframe follows");
    }
    return {std::move(columns_), std::move(times_s_), rows_, std::move(lines_), origin_,
            columns_line};
  }

 private:
  std::size_t max_rows() const {
    return std::min(kMaxTrajectoryRows,
                    kMaxTrajectoryValues / std::max<std::size_t>(columns_.size(), 1));
  }

  std::string origin_;
  std::vector<TrajectoryColumn> columns_;
  std::vector<std::string> wheres_;
  std::vector<double> times_s_;
  std::vector<std::vector<double>> rows_;
  std::vector<std::size_t> lines_;
};

/// The cells of a CSV line: the text between commas, trimmed.
class Cells {
 public:
  explicit Cells(std::string_view line)
      : rest_(line),
        count_(static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1) {}

  std::size_t count() const { return count_; }

  /// The next cell; only count() times.
  std::string_view next() {
    const auto comma = rest_.find(',');
    const std::string_view cell = rest_.substr(0, comma);
    rest_.remove_prefix(comma == std::string_view::npos ? rest_.size() : comma + 1);
    return trim(cell);
  }

 private:
  std::string_view rest_;
  std::size_t count_;
};

Trajectory parse_csv(const std::string& text, const std::string& origin) {
  TrajectoryBuilder builder(origin);
  Lines lines(text);
  std::string_view line;
  std::size_t number = 0;
  if (!lines.next(line, number)) {
    builder.fail_at_end(
        "no header: the first line that is neither blank nor a comment names the "
        "columns, e.g. time,shoulder_pan,gripper:raw");
  }
  const std::size_t header_line = number;
  Cells header(line);
  const std::string_view first = header.next();
  if (!is_time_name(first)) {
    builder.fail(header_line,
                 "the header's first cell must be time (seconds), not " + in_quotes(first));
  }
  if (header.count() == 1) {
    builder.fail(header_line, "the header names no joint after time");
  }
  if (header.count() - 1 > kMaxTrajectoryColumns) {
    builder.fail(header_line, kTooManyJoints);
  }
  for (std::size_t c = 1; c < header.count(); ++c) {
    const std::string_view cell = header.next();
    const std::string where = "column " + std::to_string(c + 1);
    if (cell.empty()) {
      builder.fail(header_line, where + " is empty");
    }
    builder.add_column(cell, header_line, where + " " + in_quotes(cell));
  }

  while (lines.next(line, number)) {
    Cells cells(line);
    if (cells.count() != header.count()) {
      builder.fail(number, "has " + std::to_string(cells.count()) + " cells, the header has " +
                               std::to_string(header.count()));
    }
    builder.start_row(number, builder.time(cells.next(), number));
    for (std::size_t c = 0; c < builder.column_count(); ++c) {
      builder.push_value(builder.value(cells.next(), c, number));
    }
  }
  return std::move(builder).build(header_line);
}

/// One JSON line read by nlohmann's SAX parser into its members, in the order written. Only a flat
/// object of numbers is accepted; anything else stops the parse with `error` set. No document is
/// built, so a hostile line costs no more memory than its members.
class FlatObjectReader : public nlohmann::json_sax<nlohmann::json> {
 public:
  /// The members read, in order; the values are numbers as doubles (not yet checked finite).
  std::vector<std::pair<std::string, double>> members;
  /// Why the line was refused; empty when it was not.
  std::string error;

  bool null() override { return not_a_number("null"); }
  bool boolean(bool /*value*/) override { return not_a_number("true or false"); }
  bool number_integer(number_integer_t value) override {
    return number(static_cast<double>(value));
  }
  bool number_unsigned(number_unsigned_t value) override {
    return number(static_cast<double>(value));
  }
  bool number_float(number_float_t value, const string_t& /*text*/) override {
    return number(value);
  }
  bool string(string_t& /*value*/) override { return not_a_number("a string"); }
  bool binary(binary_t& /*value*/) override { return not_a_number("binary data"); }
  bool start_object(std::size_t /*elements*/) override {
    if (in_object_) {
      return not_a_number("an object");
    }
    in_object_ = true;
    return true;
  }
  bool key(string_t& name) override {
    if (members.size() == kMaxKeys) {
      return refuse(kTooManyJoints);
    }
    members.emplace_back(std::move(name), 0);
    return true;
  }
  bool end_object() override { return true; }
  bool start_array(std::size_t /*elements*/) override { return not_a_number("an array"); }
  bool end_array() override { return true; }
  bool parse_error(std::size_t position, const std::string& last_token,
                   const nlohmann::detail::exception& ex) override {
    // nlohmann-json reads JSON's numbers into doubles, and refuses one beyond a double's range
    // as its error 406 rather than reading infinity.
    constexpr int kNumberOverflow = 406;
    if (ex.id == kNumberOverflow) {
      return refuse("has a number too large to be read: " + in_quotes(last_token));
    }
    // nlohmann-json's own words say what it expected ("syntax error while parsing object -
    // unexpected end of input; expected '}'"); the line and column it counts are within this one
    // line, so only the character is kept.
    const std::string_view what = ex.what();
    const auto words = what.find("syntax error");
    const std::string detail = words == std::string_view::npos
                                   ? "syntax error"
                                   : printable(what.substr(words), kMaxDetail);
    return refuse("is not JSON: " + detail + " (at character " + std::to_string(position) + ")");
  }

 private:
  /// The members a line may have: every joint, and the time (spelled twice, which is refused
  /// later with a clearer message).
  static constexpr std::size_t kMaxKeys = kMaxTrajectoryColumns + kTimeNames.size();

  bool refuse(std::string reason) {
    error = std::move(reason);
    return false;
  }
  bool not_a_number(const std::string& what) {
    if (!in_object_ || members.empty()) {
      return refuse(kNotAnObject);
    }
    return refuse("the value of " + in_quotes(members.back().first) + " is " + what +
                  ", not a number");
  }
  bool number(double value) {
    if (!in_object_ || members.empty()) {
      return refuse(kNotAnObject);
    }
    members.back().second = value;
    return true;
  }

  static constexpr const char* kNotAnObject =
      "must be a JSON object like {\"time\": 0.5, \"shoulder_pan\": 10}";
  bool in_object_ = false;
};

Trajectory parse_json_lines(const std::string& text, const std::string& origin) {
  TrajectoryBuilder builder(origin);
  Lines lines(text);
  std::string_view line;
  std::size_t number = 0;
  // The first object's keys: each key's column (kTime for the time), and the keys in value order
  // (the time's first, then each column's).
  constexpr std::size_t kTime = static_cast<std::size_t>(-1);
  std::unordered_map<std::string, std::size_t> columns;
  std::vector<std::string> keys;
  std::size_t first_line = 0;

  while (lines.next(line, number)) {
    FlatObjectReader reader;
    bool parsed = false;
    try {
      parsed = nlohmann::json::sax_parse(line.begin(), line.end(), &reader);
    } catch (const nlohmann::json::exception&) {
      // The reader's parse_error() answers every syntax error; this is a guard, not a path.
    }
    if (!parsed || !reader.error.empty()) {
      builder.fail(number, reader.error.empty() ? "is not JSON" : reader.error);
    }
    if (first_line == 0) {
      first_line = number;
      std::set<std::string_view> seen;
      for (const auto& [key, value] : reader.members) {
        if (!seen.insert(key).second) {
          builder.fail(number, "has " + in_quotes(key) + " twice");
        }
      }
      for (const auto& [key, value] : reader.members) {
        if (is_time_name(key)) {
          if (!keys.empty()) {
            builder.fail(number,
                         "has two times, " + in_quotes(keys.front()) + " and " + in_quotes(key));
          }
          keys.push_back(key);
        }
      }
      if (keys.empty()) {
        builder.fail(number, "has no \"time\" (seconds)");
      }
      columns.emplace(keys.front(), kTime);
      for (const auto& [key, value] : reader.members) {
        if (!is_time_name(key)) {
          builder.add_column(key, number, "key " + in_quotes(key));
          columns.emplace(key, builder.column_count() - 1);
          keys.push_back(key);
        }
      }
      if (builder.column_count() == 0) {
        builder.fail(number, "names no joint beside the time");
      }
    }

    // Each key's value in column order; the time first.
    std::vector<std::optional<double>> values(keys.size());
    for (const auto& [key, value] : reader.members) {
      const auto found = columns.find(key);
      if (found == columns.end()) {
        builder.fail(number, "has " + in_quotes(key) + ", which the first object (line " +
                                 std::to_string(first_line) + ") has not");
      }
      const std::size_t at = found->second == kTime ? 0 : found->second + 1;
      if (values[at]) {
        builder.fail(number, "has " + in_quotes(key) + " twice");
      }
      if (!std::isfinite(value)) {
        builder.fail(number, "the value of " + in_quotes(key) + " is not a finite number");
      }
      values[at] = value;
    }
    for (std::size_t k = 0; k < keys.size(); ++k) {
      if (!values[k]) {
        builder.fail(number, "has no " + in_quotes(keys[k]) + " (every line has the keys of the " +
                                 "first object, line " + std::to_string(first_line) + ")");
      }
    }
    builder.start_row(number, *values[0]);
    for (std::size_t c = 0; c < builder.column_count(); ++c) {
      builder.push_value(builder.checked_value(*values[c + 1], c, number));
    }
  }
  if (first_line == 0) {
    builder.fail_at_end(
        "no keyframe: each line that is neither blank nor a comment is one "
        "JSON object, e.g. {\"time\": 0, \"shoulder_pan\": 10}");
  }
  return std::move(builder).build(first_line);
}

}  // namespace

TrajectoryFormat trajectory_format(const std::filesystem::path& path, const std::string& text) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](char c) {
    return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;
  });
  if (extension == ".csv") {
    return TrajectoryFormat::Csv;
  }
  if (extension == ".jsonl" || extension == ".ndjson") {
    return TrajectoryFormat::JsonLines;
  }
  Lines lines(text);
  std::string_view line;
  std::size_t number = 0;
  if (lines.next(line, number) && trim(line).starts_with('{')) {
    return TrajectoryFormat::JsonLines;
  }
  return TrajectoryFormat::Csv;
}

model::Trajectory parse_trajectory(const std::string& text, const std::string& origin,
                                   TrajectoryFormat format) {
  return format == TrajectoryFormat::Csv ? parse_csv(text, origin) : parse_json_lines(text, origin);
}

model::Trajectory read_trajectory_file(const std::filesystem::path& path) {
  const std::string origin = path.string();
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error) {
    throw ConfigError(origin, "", "cannot be read: " + error.message());
  }
  if (size > kMaxTrajectoryFileBytes) {
    throw ConfigError(origin, "",
                      "is larger than " + std::to_string(kMaxTrajectoryFileBytes >> 20) +
                          " MiB, the most a trajectory file may be");
  }
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in || !in.read(text.data(), static_cast<std::streamsize>(size))) {
    throw ConfigError(origin, "", "cannot be read");
  }
  return parse_trajectory(text, origin, trajectory_format(path, text));
}

}  // namespace dxlemu::app
