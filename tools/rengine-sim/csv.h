// CSV fields as rengine-sim writes them (the trajectory and the ray answers).
#pragma once

#include <string>

namespace REngine::sim {

// RFC 4180: a field holding a comma, a quote or a line break is quoted, quotes doubled.
inline std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + '"';
}

}  // namespace REngine::sim
