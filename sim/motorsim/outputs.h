// outputs.h - the files motorsim writes. Each is written to a temporary
// name in the destination directory and renamed into place, so a reader
// never sees a half-written file and a failed run leaves no output.
#ifndef MCSIM_MOTORSIM_OUTPUTS_H
#define MCSIM_MOTORSIM_OUTPUTS_H

#include <cstdio>
#include <string>
#include <vector>

#include "motorsim/metrics.h"

namespace mcsim {

// Throw std::runtime_error("PATH: reason") on any I/O failure.
// Any table of doubles, row-major, n_cols names.
void write_table_csv_atomic(const std::string& path, const char* const* names, int n_cols, const double* data,
                            std::size_t n_rows);
void write_metrics_json_atomic(const std::string& path, const MetricList& m);

// SIGINT, SIGTERM, SIGHUP remove the output's temporary file (if one is
// being written) and end the process with that signal. Call once in main.
void install_output_signal_handlers();

// `key value` lines, one metric per line.
void print_metrics(std::FILE* f, const MetricList& m);

// Runs `python script csv png`; returns "" on success, else a reason.
std::string run_plot(const std::string& python, const std::string& script, const std::string& csv,
                     const std::string& png);

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_OUTPUTS_H
