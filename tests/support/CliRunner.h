// rengine-sim run through the shell, for the CLI tests: its exit code and output, the
// trajectory CSV parsed, and a scratch directory per test (the Cli fixture); numbers and
// vectors written into scene JSON exactly, a row's state as vectors, the run's hash= and the
// CSV's lines from a step on. Shared by the cli_tests suites. Needs RENGINE_SIM (the binary)
// at build time.
#pragma once

#include <REngineMath/RMath.h>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace REngine::test {

namespace fs = std::filesystem;

inline const std::string kHeader = "step,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";

struct Result {
  int code = -1;
  std::string out, err;
  std::string LastErrLine() const {
    std::string s = err;
    while (!s.empty() && s.back() == '\n') s.pop_back();
    return s.substr(s.find_last_of('\n') + 1);  // npos + 1 == 0
  }
};

struct Row {
  std::uint64_t step = 0;
  double time = 0;
  std::string body;
  std::array<double, 13> state{};  // x y z qw qx qy qz vx vy vz wx wy wz
};

inline std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream s(line);
  for (std::string f; std::getline(s, f, ',');) fields.push_back(f);
  return fields;
}

// The rows of a trajectory whose body names hold no commas; checks the header on the way.
inline std::vector<Row> ParseCsv(const std::string& text) {
  std::vector<Row> rows;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, kHeader);
  while (std::getline(in, line)) {
    const std::vector<std::string> f = Split(line);
    EXPECT_EQ(f.size(), 16u) << line;
    if (f.size() != 16) break;
    Row r;
    r.step = std::stoull(f[0]);
    r.time = std::strtod(f[1].c_str(), nullptr);
    r.body = f[2];
    for (int i = 0; i < 13; ++i) r.state[i] = std::strtod(f[3 + i].c_str(), nullptr);
    rows.push_back(r);
  }
  return rows;
}

// A row's state, world frame: the shape frame's position (m), the centre of mass's velocity
// (m/s), the angular velocity (rad/s).
// The rows of one body, in step order.
inline std::vector<Row> RowsOf(const std::vector<Row>& rows, const std::string& body) {
  std::vector<Row> out;
  for (const Row& r : rows) {
    if (r.body == body) out.push_back(r);
  }
  return out;
}

inline RVec3 Position(const Row& r) { return RVec3(r.state[0], r.state[1], r.state[2]); }
inline RVec3 Velocity(const Row& r) { return RVec3(r.state[7], r.state[8], r.state[9]); }
inline RVec3 AngularVelocity(const Row& r) { return RVec3(r.state[10], r.state[11], r.state[12]); }

// The lines of a CSV whose first field (the step) is at least `from`, header excluded: rows
// compared as text, bit for bit.
inline std::vector<std::string> RowsFrom(const std::string& csv, std::uint64_t from) {
  std::vector<std::string> rows;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    if (std::stoull(line.substr(0, line.find(','))) >= from) rows.push_back(line);
  }
  return rows;
}

// A number for scene JSON that reads back as the same double; a vector of three.
inline std::string Number(double x) {
  char s[32];
  std::snprintf(s, sizeof s, "%.17g", x);
  return s;
}
inline std::string Vec(const RVec3& v) {
  return "[" + Number(v.x()) + ", " + Number(v.y()) + ", " + Number(v.z()) + "]";
}

inline std::string Quote(const fs::path& p) { return "'" + p.string() + "'"; }

// Each test gets its own scratch directory, removed afterwards.
class Cli : public testing::Test {
 protected:
  void SetUp() override {
    const std::string test = testing::UnitTest::GetInstance()->current_test_info()->name();
    m_dir = fs::temp_directory_path() / ("rengine_cli_" + test + "_" + std::to_string(::getpid()));
    fs::remove_all(m_dir);
    fs::create_directories(m_dir);
  }
  void TearDown() override { fs::remove_all(m_dir); }

  fs::path Path(const std::string& name) const { return m_dir / name; }
  fs::path Write(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name), std::ios::binary) << text;
    return Path(name);
  }

  // rengine-sim with `args` (already shell-quoted where needed).
  Result Run(const std::string& args) const {
    const std::string command = Quote(RENGINE_SIM) + " " + args + " >" + Quote(Path("stdout")) +
                                " 2>" + Quote(Path("stderr"));
    const int status = std::system(command.c_str());
    Result r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = ReadFile(Path("stdout"));
    r.err = ReadFile(Path("stderr"));
    return r;
  }

  fs::path m_dir;
};

// "hash=<16 hex digits>" from a run's summary line, or what the line was instead.
inline std::string Hash(const Result& r) {
  const std::string line = r.LastErrLine();
  const std::size_t at = line.find("hash=");
  return at == std::string::npos ? "(no hash: " + line + ")" : line.substr(at);
}

// One body per entry; `fields` are the body's fields after its name.
inline std::string SceneOf(const std::vector<std::pair<std::string, std::string>>& bodies,
                    const std::string& top = R"("dt": 0.01, "steps": 10)") {
  std::string s = "{" + top + R"(, "bodies": [)";
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    s += (i ? ",\n" : "\n") + std::string(R"({"name": ")") + bodies[i].first + "\", " +
         bodies[i].second + "}";
  }
  return s + "]}";
}

inline const std::string kSphere = R"("shape": {"type": "sphere", "radius": 0.5})";

}  // namespace REngine::test
