// rengine-bench's report (report.h): the table and the CSV, with the same rows.
#include "report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace rbench {

namespace {

std::string Number(const std::optional<double>& x, const char* format) {
  if (!x) return "";
  char text[32];
  std::snprintf(text, sizeof text, format, *x);
  return text;
}

std::string DtLabel(RScalar dt) {
  return "1/" + std::to_string(std::llround(1 / dt));
}

}  // namespace

double Median(std::vector<double> xs) {
  std::sort(xs.begin(), xs.end());
  const std::size_t n = xs.size();
  return n % 2 ? xs[n / 2] : 0.5 * (xs[n / 2 - 1] + xs[n / 2]);
}

void PrintTableHeader() {
  std::printf("%-15s %-8s %-6s %5s %11s %11s %13s %15s\n", "scene", "method", "dt", "iter",
              "ms/step", "error", "energy_drift", "momentum_drift");
}

void PrintRow(const Row& r) {
  std::printf("%-15s %-8s %-6s %5s %11.4g %11s %13s %15s\n", r.scene, MethodName(r.method),
              DtLabel(r.dt).c_str(), r.iterations ? std::to_string(*r.iterations).c_str() : "-",
              r.msPerStep, Number(r.errors.error, "%.3e").c_str(),
              Number(r.errors.energyDrift, "%.3e").c_str(),
              Number(r.errors.momentumDrift, "%.3e").c_str());
  std::fflush(stdout);
}

bool WriteCsv(const std::string& path, const std::vector<Row>& rows) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) return false;
  std::fprintf(file,
               "scene,method,dt,iterations,ms_per_step,error,energy_drift,momentum_drift\n");
  for (const Row& r : rows) {
    std::fprintf(file, "%s,%s,%.17g,%s,%.6g,%s,%s,%s\n", r.scene, MethodName(r.method), r.dt,
                 r.iterations ? std::to_string(*r.iterations).c_str() : "", r.msPerStep,
                 Number(r.errors.error, "%.6e").c_str(),
                 Number(r.errors.energyDrift, "%.6e").c_str(),
                 Number(r.errors.momentumDrift, "%.6e").c_str());
  }
  const bool ok = !std::ferror(file);
  return std::fclose(file) == 0 && ok;
}

}  // namespace rbench
