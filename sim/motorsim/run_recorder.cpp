#include "motorsim/run_recorder.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "host_drives/host_drive.h"
#include "motorsim/ekf_speed_recorder.h"
#include "motorsim/outputs.h"
#include "motorsim/position_recorder.h"
#include "motorsim/speed_recorder.h"

namespace mcsim {

RunRecorder::RunRecorder(const Scenario& sc, const PmPlant& plant, const drive_t& drive, const char* const* columns,
                         int n_columns, bool record_rows)
    : sc_(sc),
      plant_(plant),
      drive_(drive),
      signals_(drive),
      signal_columns_(signals_.columns()),
      columns_(columns, columns + n_columns),
      n_own_(n_columns),
      n_max_(sc.n_ticks()),
      watch_(sc)
{
    for (const int k : signal_columns_) {
        const char* name = signals_.at(static_cast<std::size_t>(k)).name;
        for (int c = 0; c < n_own_; ++c) {
            if (std::strcmp(columns[c], name) == 0) {
                throw std::logic_error(std::string("the ") + drive.ops->name + " drive's signal '" + name +
                                       "' has the name of a column of its scoring");
            }
        }
        columns_.push_back(name);
    }
    // One row per period, allocated and zeroed here: the loop itself
    // neither allocates nor takes first-touch page faults.
    if (record_rows) {
        rows_.assign(static_cast<std::size_t>(n_max_) * columns_.size(), 0.0);
    }
}

void RunRecorder::monitor(void* ctx, const hal_sw_plant_period_t* p) { static_cast<RunRecorder*>(ctx)->record(*p); }

void RunRecorder::record(const hal_sw_plant_period_t& p)
{
    if (n_ >= n_max_) {
        return;  // more periods than the scenario asked for: keep the log bounded
    }
    double* row = rows_.empty() ? nullptr : &rows_[static_cast<std::size_t>(n_) * columns_.size()];
    signals_.read();
    const std::int64_t fault = on_period(p, row);
    if (row != nullptr) {
        double* r = row + n_own_;
        for (const int k : signal_columns_) {
            *r++ = signals_.value(k);
        }
    }
    watch_.on_period(p, fault, plant_);
    n_ += 1;
}

double* RunRecorder::row_at(std::uint64_t k)
{
    if (rows_.empty() || k >= n_max_) {
        return nullptr;
    }
    return &rows_[static_cast<std::size_t>(k) * columns_.size()];
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
    write_table_csv_atomic(path, columns_.data(), static_cast<int>(columns_.size()),
                           rows_.empty() ? nullptr : rows_.data(), rows());
}

std::unique_ptr<RunRecorder> make_recorder(const Scenario& sc, const PmPlant& plant, const drive_t& d, bool record_rows)
{
    const HostDrive* host = host_drive_find(d.ops->name);
    const std::string scoring = (host != nullptr && host->scoring != nullptr)
                                    ? host->scoring
                                    : (d.ops->kind == DRIVE_KIND_POSITION ? "position" : "speed");
    if (scoring == "position") {
        return std::make_unique<PositionRecorder>(sc, plant, d, record_rows);
    }
    if (scoring == "speed") {
        return std::make_unique<SpeedRecorder>(sc, plant, d, record_rows);
    }
    if (scoring == "ekf_speed") {
        return std::make_unique<EkfSpeedRecorder>(sc, plant, d, record_rows);
    }
    throw std::logic_error(std::string("the ") + d.ops->name + " drive's host part names the scoring '" + scoring +
                           "', not one of motorsim's (position, speed, ekf_speed)");
}

}  // namespace mcsim
