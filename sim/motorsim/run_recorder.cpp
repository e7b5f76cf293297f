#include "motorsim/run_recorder.h"

#include <cmath>

#include "motorsim/outputs.h"

namespace mcsim {

RunRecorder::RunRecorder(const Scenario& sc, const PmPlant& plant, const char* const* columns, int n_columns,
                         bool record_rows)
    : sc_(sc), plant_(plant), columns_(columns), n_columns_(n_columns), n_max_(sc.n_ticks()), watch_(sc)
{
    // One row per period, allocated and zeroed here: the loop itself
    // neither allocates nor takes first-touch page faults.
    if (record_rows) {
        rows_.assign(static_cast<std::size_t>(n_max_) * static_cast<std::size_t>(n_columns_), 0.0);
    }
}

void RunRecorder::monitor(void* ctx, const hal_sw_plant_period_t* p) { static_cast<RunRecorder*>(ctx)->record(*p); }

void RunRecorder::record(const hal_sw_plant_period_t& p)
{
    if (n_ >= n_max_) {
        return;  // more periods than the scenario asked for: keep the log bounded
    }
    double* row = rows_.empty() ? nullptr : &rows_[static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_columns_)];
    const std::int64_t fault = on_period(p, row);
    watch_.on_period(p, fault, plant_);
    n_ += 1;
}

double* RunRecorder::row_at(std::uint64_t k)
{
    if (rows_.empty() || k >= n_max_) {
        return nullptr;
    }
    return &rows_[static_cast<std::size_t>(k) * static_cast<std::size_t>(n_columns_)];
}

void RunRecorder::append_run_tail(MetricList* m, double wall_loop_s, bool with_substeps) const
{
    const double sim_s = static_cast<double>(n_) * sc_.ts_s;
    m->emplace_back("n_samples", static_cast<std::int64_t>(n_));
    m->emplace_back("seed", static_cast<std::int64_t>(sc_.seed));
    if (with_substeps) {
        m->emplace_back("substeps", static_cast<std::int64_t>(plant_.substeps()));
    }
    m->emplace_back("sim_time_s", sim_s);
    m->emplace_back("wall_time_s", wall_loop_s);
    m->emplace_back("realtime_factor", wall_loop_s > 0.0 ? sim_s / wall_loop_s : NAN);
}

void RunRecorder::write_csv(const std::string& path) const
{
    write_table_csv_atomic(path, columns_, n_columns_, rows_.empty() ? nullptr : rows_.data(), rows());
}

}  // namespace mcsim
