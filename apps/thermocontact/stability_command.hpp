#pragma once
// `thermocontact stability CASE.toml [--output DIR] [--set KEY=VALUE]`: the linear stability
// analysis of the case's steady sliding (src/tc/stability) and its files — stability.json,
// stability.csv, the leading mode of each speed (mode_<i>.vtu) and the critical one
// (mode_critical.vtu) — in the output directory (docs/case-format.md, "Stability analysis").
// Exit codes as `run`'s: 0 done, 1 a numerical or run-time failure, 2 bad input.
#include <string>
#include <vector>

[[nodiscard]] int stability_command(const std::string& case_file,
                                    const std::vector<std::string>& overrides,
                                    const std::string& output, const char* program);
