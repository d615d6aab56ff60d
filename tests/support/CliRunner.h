// rengine-sim run through the shell, for the CLI tests: its exit code and output, the
// trajectory CSV parsed, and a scratch directory per test (the Cli fixture). Shared by
// cli_test.cpp and body_kinds_cli_test.cpp. Needs RENGINE_SIM (the binary) at build time.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdint>
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
