// CSV fields as rengine-sim writes them (the trajectory, the ray answers, the events).
#pragma once

#include <charconv>
#include <string>

namespace REngine::sim {

// RFC 4180: a field holding a comma, a quote or a line break is quoted, quotes doubled.
inline std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + '"';
}

// A comma, then the number with full precision: std::to_chars with precision 17 writes
// exactly what printf's %.17g does (the standard defines it so), three times faster.
inline void AppendNumber(std::string& out, double value) {
  char text[40];
  text[0] = ',';
  const char* end = std::to_chars(text + 1, text + sizeof text, value, std::chars_format::general, 17).ptr;
  out.append(text, static_cast<std::size_t>(end - text));
}

}  // namespace REngine::sim
