// Trajectory files (docs/hands.md "File formats"): what CSV and JSON lines files build, how the
// format is chosen, and that every malformed file is refused naming its line and the reason.
#include <catch2/catch.hpp>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "app/config/bus_config.hpp"
#include "app/config/trajectory_file.hpp"
#include "model/hand/trajectory.hpp"
#include "temp_dir.hpp"

using namespace dxlemu;
using app::TrajectoryFormat;
using model::JointUnit;
using model::TrajectoryColumn;

namespace trajectory_file_test_helpers {

/// What parsing `text` as file "pick.csv" in `format` says: the error message, or "accepted".
std::string trajectory_refusal(const std::string& text,
                               TrajectoryFormat format = TrajectoryFormat::Csv) {
  try {
    app::parse_trajectory(text, "pick.csv", format);
  } catch (const app::ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

/// Every row's time and the value of each column, row by row.
std::vector<std::vector<double>> keyframes(const model::Trajectory& t) {
  std::vector<std::vector<double>> rows;
  for (std::size_t r = 0; r < t.row_count(); ++r) {
    rows.push_back({t.times_s()[r]});
    for (std::size_t c = 0; c < t.columns().size(); ++c) {
      rows.back().push_back(t.value(r, c));
    }
  }
  return rows;
}

std::vector<std::size_t> lines_of(const model::Trajectory& t) {
  std::vector<std::size_t> lines;
  for (std::size_t r = 0; r < t.row_count(); ++r) {
    lines.push_back(t.line(r));
  }
  return lines;
}

void write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace trajectory_file_test_helpers

using trajectory_file_test_helpers::keyframes;
using trajectory_file_test_helpers::lines_of;
using trajectory_file_test_helpers::trajectory_refusal;

TEST_CASE("A CSV trajectory names its joints in the header, with units and servo IDs",
          "[app][trajectory]") {
  const auto t = app::parse_trajectory(
      "# picked by hand\n"
      "\n"
      "time,shoulder_pan,3:raw,gripper:deg\n"
      "0,0,2048,10\n"
      "   # a comment between rows\n"
      "0.5,-12.5,+2100,1e1\n"
      "\n"
      "2,.5,1900,-0\n",
      "pick.csv", TrajectoryFormat::Csv);
  CHECK(t.origin() == "pick.csv");
  CHECK(t.columns() == std::vector<TrajectoryColumn>{{"shoulder_pan", JointUnit::Degrees},
                                                     {"3", JointUnit::Raw},
                                                     {"gripper", JointUnit::Degrees}});
  CHECK(keyframes(t) == std::vector<std::vector<double>>{
                            {0, 0, 2048, 10}, {0.5, -12.5, 2100, 10}, {2, 0.5, 1900, 0}});
  CHECK(lines_of(t) == std::vector<std::size_t>{4, 6, 8});
  CHECK(t.columns_line() == 3);
}

TEST_CASE("A CSV trajectory may have CRLF, a byte order mark and spaces around cells",
          "[app][trajectory]") {
  const auto t = app::parse_trajectory(
      "\xEF\xBB\xBFtime_s , wrist.roll-2 :raw\r\n# note\r\n 0.25 ,\t7 \r\n1,8\r\n", "a.csv",
      TrajectoryFormat::Csv);
  CHECK(t.columns() == std::vector<TrajectoryColumn>{{"wrist.roll-2", JointUnit::Raw}});
  CHECK(keyframes(t) == std::vector<std::vector<double>>{{0.25, 7}, {1, 8}});
  CHECK(lines_of(t) == std::vector<std::size_t>{3, 4});
  // "t" spells the time too; a file need not end with a line break.
  CHECK(keyframes(app::parse_trajectory("t,a\n0,1", "a.csv", TrajectoryFormat::Csv)) ==
        std::vector<std::vector<double>>{{0, 1}});
}

TEST_CASE("A JSON lines trajectory takes its columns from the first object, in order",
          "[app][trajectory]") {
  const auto t = app::parse_trajectory(
      "# recorded\n"
      "{\"time\": 0, \"shoulder_pan\": 10.0, \"gripper:raw\": 2048, \"3\": 0}\n"
      "\r\n"
      "{\"3\": -1.5, \"gripper:raw\": 2100, \"time\": 0.5, \"shoulder_pan\": 20}\r\n"
      "  {\"time\":1,\"shoulder_pan\":30,\"gripper:raw\":1e3,\"3\":2}\n",
      "pick.jsonl", TrajectoryFormat::JsonLines);
  CHECK(t.columns() == std::vector<TrajectoryColumn>{{"shoulder_pan", JointUnit::Degrees},
                                                     {"gripper", JointUnit::Raw},
                                                     {"3", JointUnit::Degrees}});
  CHECK(keyframes(t) == std::vector<std::vector<double>>{
                            {0, 10, 2048, 0}, {0.5, 20, 2100, -1.5}, {1, 30, 1000, 2}});
  CHECK(lines_of(t) == std::vector<std::size_t>{2, 4, 5});
  CHECK(t.columns_line() == 2);
  // The time may be anywhere in the first object too, and spelled time_s or t.
  const auto u = app::parse_trajectory("{\"a\": 1, \"t\": 0}\n{\"t\": 1, \"a\": 2}", "u.jsonl",
                                       TrajectoryFormat::JsonLines);
  CHECK(keyframes(u) == std::vector<std::vector<double>>{{0, 1}, {1, 2}});
}

TEST_CASE("A trajectory file's format follows its extension, else its first line",
          "[app][trajectory]") {
  const std::string json = "# c\n\n  {\"time\": 0, \"a\": 1}\n";
  const std::string csv = "# c\ntime,a\n0,1\n";
  CHECK(app::trajectory_format("a.csv", json) == TrajectoryFormat::Csv);
  CHECK(app::trajectory_format("a.CSV", json) == TrajectoryFormat::Csv);
  CHECK(app::trajectory_format("a.jsonl", csv) == TrajectoryFormat::JsonLines);
  CHECK(app::trajectory_format("dir/a.ndjson", csv) == TrajectoryFormat::JsonLines);
  CHECK(app::trajectory_format("a.txt", json) == TrajectoryFormat::JsonLines);
  CHECK(app::trajectory_format("a", csv) == TrajectoryFormat::Csv);
  CHECK(app::trajectory_format("a", "") == TrajectoryFormat::Csv);
}

TEST_CASE("A malformed CSV trajectory is refused with its line and the reason",
          "[app][trajectory]") {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"",
       "end of file: no header: the first line that is neither blank nor a comment names the "
       "columns, e.g. time,shoulder_pan,gripper:raw"},
      {"# only a comment\n\n",
       "end of file: no header: the first line that is neither blank nor "
       "a comment names the columns, e.g. time,shoulder_pan,gripper:raw"},
      {"\n0,1\n", "line 2: the header's first cell must be time (seconds), not \"0\""},
      {"a,time\n", "line 1: the header's first cell must be time (seconds), not \"a\""},
      {"time\n0\n", "line 1: the header names no joint after time"},
      {"time,a,,b\n", "line 1: column 3 is empty"},
      {"time,a,a:raw\n", "line 1: column 3 \"a:raw\": joint a already has column 2 \"a\""},
      {"time,a:pct\n",
       "line 1: column 2 \"a:pct\": unknown unit \"pct\" (write NAME:deg or NAME:raw)"},
      {"time,a:deg:raw\n",
       "line 1: column 2 \"a:deg:raw\": unknown unit \"deg:raw\" (write NAME:deg or NAME:raw)"},
      {"time,:raw\n", "line 1: column 2 \":raw\": no joint name"},
      {"time,a b\n",
       "line 1: column 2 \"a b\": \"a b\" is neither a joint name (letters, "
       "digits, _, - and .) nor a servo ID"},
      {"time,a,t\n", "line 1: column 3 \"t\": \"t\" names the time, which comes once"},
      {"# c\ntime,a\n# c\n", "line 2: no keyframe follows"},
      {"time,a,b\n0,1,2\n# c\n1,2,3,4,5\n", "line 4: has 5 cells, the header has 3"},
      {"time,a,b\n0,1\n", "line 2: has 2 cells, the header has 3"},
      {"time,a\n0,1,\n", "line 2: has 3 cells, the header has 2"},
      {"time,a\n0,abc\n", "line 2: column 2 \"a\": \"abc\" is not a finite number"},
      {"time,a\n0,\n", "line 2: column 2 \"a\": \"\" is not a finite number"},
      {"time,a\n0,nan\n", "line 2: column 2 \"a\": \"nan\" is not a finite number"},
      {"time,a\n0,-inf\n", "line 2: column 2 \"a\": \"-inf\" is not a finite number"},
      {"time,a\n0,1e400\n", "line 2: column 2 \"a\": \"1e400\" is not a finite number"},
      {"time,a\n0,0x10\n", "line 2: column 2 \"a\": \"0x10\" is not a finite number"},
      {"time,a\n0,1.5.2\n", "line 2: column 2 \"a\": \"1.5.2\" is not a finite number"},
      {"time,a\n0,+-1\n", "line 2: column 2 \"a\": \"+-1\" is not a finite number"},
      {"time,a\n0,1 2\n", "line 2: column 2 \"a\": \"1 2\" is not a finite number"},
      {"time,a\n0,1e13\n",
       "line 2: column 2 \"a\": 1e+13 is larger in magnitude than 1e+12, "
       "the most a trajectory value may be"},
      {"time,a\nx,1\n", "line 2: time \"x\" is not a finite number"},
      {"time,a\n-0.5,1\n", "line 2: time -0.5 s is negative: a trajectory starts at 0 s"},
      {"time,a\n0,1\n\n1.5,1\n# c\n1.2,1\n",
       "line 6: time 1.2 s is not after the previous row's 1.5 s"},
      {"time,a\n1.5,1\n1.5,1\n", "line 3: time 1.5 s is not after the previous row's 1.5 s"},
      {"time,a\n0,1\n0.0000001,1\n",
       "line 3: time 1e-07 s is less than 1e-06 s after the previous row's 0 s"},
      {"time,a\n2e9,1\n",
       "line 2: time 2e+09 s is later than 1e+09 s, the latest a keyframe may be"},
  };
  for (const auto& [text, message] : cases) {
    INFO(text);
    CHECK(trajectory_refusal(text) == "pick.csv: " + message);
  }
  // A long or binary cell is quoted short, in printable characters.
  CHECK(trajectory_refusal("time,a\n0," + std::string(100, 'x') + "\x01\n") ==
        "pick.csv: line 2: column 2 \"a\": \"" + std::string(40, 'x') +
            "...\" is not a finite number");
  CHECK(trajectory_refusal("time,a\x80\n") ==
        "pick.csv: line 1: column 2 \"a?\": \"a?\" is neither a joint name (letters, digits, _, "
        "- and .) nor a servo ID");
}

TEST_CASE("A malformed JSON lines trajectory is refused with its line and the reason",
          "[app][trajectory]") {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"# c\n",
       "end of file: no keyframe: each line that is neither blank nor a comment is one "
       "JSON object, e.g. {\"time\": 0, \"shoulder_pan\": 10}"},
      {"[1, 2]\n", "line 1: must be a JSON object like {\"time\": 0.5, \"shoulder_pan\": 10}"},
      {"5\n", "line 1: must be a JSON object like {\"time\": 0.5, \"shoulder_pan\": 10}"},
      {"{\"time\": 0, \"a\": \"x\"}", "line 1: the value of \"a\" is a string, not a number"},
      {"{\"time\": 0, \"a\": true}", "line 1: the value of \"a\" is true or false, not a number"},
      {"{\"time\": 0, \"a\": null}", "line 1: the value of \"a\" is null, not a number"},
      {"{\"time\": 0, \"a\": [1]}", "line 1: the value of \"a\" is an array, not a number"},
      {"{\"time\": 0, \"a\": {\"b\": 1}}", "line 1: the value of \"a\" is an object, not a number"},
      {"{\"time\": 0, \"a\": 1e400}", "line 1: has a number too large to be read: \"1e400\""},
      {"{\"a\": 1}", "line 1: has no \"time\" (seconds)"},
      {"{\"time\": 0, \"a\": 1, \"t\": 1}", "line 1: has two times, \"time\" and \"t\""},
      {"{\"time\": 0}", "line 1: names no joint beside the time"},
      {"{}", "line 1: has no \"time\" (seconds)"},
      {"{\"time\": 0, \"a\": 1, \"a\": 2}", "line 1: has \"a\" twice"},
      {"{\"time\": 0, \"a\": 1}\n{\"time\": 1, \"a\": 1, \"time\": 2}",
       "line 2: has \"time\" twice"},
      {"{\"time\": 0, \"a:pct\": 1}",
       "line 1: key \"a:pct\": unknown unit \"pct\" (write NAME:deg or NAME:raw)"},
      {"{\"time\": 0, \"a\": 1, \"a:raw\": 1}",
       "line 1: key \"a:raw\": joint a already has key \"a\""},
      {"{\"time\": 0, \"a\": 1, \"b\": 2}\n# c\n{\"time\": 1, \"a\": 2}",
       "line 3: has no \"b\" (every line has the keys of the first object, line 1)"},
      {"{\"time\": 0, \"a\": 1}\n{\"time\": 1, \"a\": 2, \"c\": 3}",
       "line 2: has \"c\", which the first object (line 1) has not"},
      {"{\"time\": 0, \"a\": 1}\n{\"t\": 1, \"a\": 2}",
       "line 2: has \"t\", which the first object (line 1) has not"},
      {"{\"time\": 0, \"a\": 1}\n{\"time\": 0, \"a\": 2}",
       "line 2: time 0 s is not after the previous row's 0 s"},
      {"{\"time\": -1, \"a\": 1}", "line 1: time -1 s is negative: a trajectory starts at 0 s"},
      {"{\"time\": 0, \"a\": -2e12}",
       "line 1: key \"a\": -2e+12 is larger in magnitude than "
       "1e+12, the most a trajectory value may be"},
  };
  for (const auto& [text, message] : cases) {
    INFO(text);
    CHECK(trajectory_refusal(text, TrajectoryFormat::JsonLines) == "pick.csv: " + message);
  }
  CHECK(trajectory_refusal("{\"time\": 0, \"a\": 1", TrajectoryFormat::JsonLines) ==
        "pick.csv: line 1: is not JSON: syntax error while parsing object - unexpected end of "
        "input; expected '}' (at character 19)");
  for (const std::string text :
       {"{\"time\": 0, \"a\": 1", "{\"time\": 0, \"a\": 1} x", "{\"time\": 0, 'a': 1}",
        "{\"time\": 0, \"a\": 01}", "{\"time\": 0, \"\xff\": 1}"}) {
    INFO(text);
    CHECK_THAT(trajectory_refusal(text, TrajectoryFormat::JsonLines),
               Catch::StartsWith("pick.csv: line 1: is not JSON: syntax error while parsing "));
  }
}

TEST_CASE("A trajectory file may name at most 256 joints", "[app][trajectory]") {
  std::string header = "time";
  std::string object = "{\"time\": 0";
  for (int j = 0; j < 257; ++j) {
    header += ",j" + std::to_string(j);
    object += ", \"j" + std::to_string(j) + "\": 0";
  }
  CHECK(trajectory_refusal(header + "\n") ==
        "pick.csv: line 1: more than 256 joints, the most a trajectory may have");
  CHECK(trajectory_refusal(object + "}", TrajectoryFormat::JsonLines) ==
        "pick.csv: line 1: more than 256 joints, the most a trajectory may have");
}

TEST_CASE("A trajectory file may hold at most a million keyframes", "[app][trajectory]") {
  std::string text = "time,a\n";
  text.reserve(16'000'000);
  for (std::size_t r = 0; r <= app::kMaxTrajectoryRows; ++r) {
    text += std::to_string(r) + ",0\n";
  }
  CHECK(trajectory_refusal(text) ==
        "pick.csv: line 1000002: more than 1000000 keyframes: a trajectory may have at most "
        "1000000 keyframes and 16000000 values (keyframes times joints)");
}

TEST_CASE("A trajectory file is read by its extension or its contents", "[app][trajectory]") {
  const dxlemu::test::TempDir dir;
  trajectory_file_test_helpers::write_file(dir.path() / "wave.txt",
                                           "{\"time\": 0, \"a\": 1}\n{\"time\": 2, \"a\": 3}\n");
  const auto t = app::read_trajectory_file(dir.path() / "wave.txt");
  CHECK(t.origin() == (dir.path() / "wave.txt").string());
  CHECK(keyframes(t) == std::vector<std::vector<double>>{{0, 1}, {2, 3}});
  trajectory_file_test_helpers::write_file(dir.path() / "wave.csv", "{\"time\": 0, \"a\": 1}\n");
  CHECK_THROWS_WITH(app::read_trajectory_file(dir.path() / "wave.csv"),
                    (dir.path() / "wave.csv").string() +
                        ": line 1: the header's first cell must be time (seconds), not "
                        "\"{\"time\": 0\"");
  CHECK_THROWS_WITH(
      app::read_trajectory_file(dir.path() / "missing.csv"),
      Catch::StartsWith((dir.path() / "missing.csv").string() + ": /: cannot be read"));
  CHECK_THROWS_WITH(app::read_trajectory_file(dir.path()),
                    Catch::StartsWith(dir.path().string() + ": /: cannot be read"));
}
