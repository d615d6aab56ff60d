// rengine-bench's report: one row per run and engine, printed as a table while the grid
// runs and written as CSV at the end:
//
//   scene,method,dt,iterations,ms_per_step,error,energy_drift,momentum_drift
#pragma once

#include "engines.h"

#include <optional>
#include <string>
#include <vector>

namespace rbench {

struct Row {
  const char* scene;
  Method method;
  RScalar dt;
  std::optional<int> iterations;
  double msPerStep;
  Errors errors;
};

// The median of `xs` (the mean of the middle two for an even count).
double Median(std::vector<double> xs);

void PrintTableHeader();
// Prints the row and flushes, so a long run shows its progress.
void PrintRow(const Row& r);
// False when the file cannot be written.
bool WriteCsv(const std::string& path, const std::vector<Row>& rows);

}  // namespace rbench
