// drive_replay - feeds recorded phase currents to the scenario's drive, open
// loop (the drive's voltages go nowhere), and writes what it estimates.
// Built in every host build, so the same currents can be replayed through
// the float and the fixed-point drive and their estimates compared sample
// by sample without the closed loop making the two runs drift apart
// (tools/checks/compare_builds.py).
//   drive_replay SCENARIO.toml CURRENTS.csv OUT.csv
// CURRENTS.csv is a motorsim CSV of a two-phase run (columns i_a_meas_A,
// i_b_meas_A, v_a_V, v_b_V); OUT.csv has t_s, mode, theta_est, omega_est, v_a, v_b.
//
// Drive-neutral, like motorsim: the scenario's drive is designed by its
// host part and run through the drive interface (drives/drive.h: step,
// status); the one thing a replay asks of a drive, how to tell it the
// voltage the recorded run really applied, is its host part's
// HostDrive.set_applied_voltage (host_drives/host_drive.h). A drive whose
// host part has none is refused. Chosen over moving the program into paper
// 000's room: the program then names no drive and replays any drive that
// answers that one question, with no copy per drive.
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "host_drives/host_drive.h"
#include "mc_convert.h"
#include "scenario/scenario.h"

namespace {

struct Sample {
    double i_a, i_b, v_a, v_b;
};

std::vector<Sample> read_currents(const std::string& path)
{
    std::ifstream in(path);
    if (!in) {
        throw std::runtime_error(path + ": cannot open");
    }
    std::string line;
    std::getline(in, line);
    std::vector<std::string> head;
    {
        std::stringstream ss(line);
        std::string cell;
        while (std::getline(ss, cell, ',')) head.push_back(cell);
    }
    int ia = -1, ib = -1, va = -1, vb = -1;
    for (std::size_t k = 0; k < head.size(); ++k) {
        if (head[k] == "i_a_meas_A") ia = static_cast<int>(k);
        if (head[k] == "i_b_meas_A") ib = static_cast<int>(k);
        if (head[k] == "v_a_V") va = static_cast<int>(k);
        if (head[k] == "v_b_V") vb = static_cast<int>(k);
    }
    if (ia < 0 || ib < 0 || va < 0 || vb < 0) {
        throw std::runtime_error(path + ": needs columns i_a_meas_A, i_b_meas_A, v_a_V, v_b_V");
    }
    std::vector<Sample> out;
    while (std::getline(in, line)) {
        std::stringstream ss(line);
        std::string cell;
        Sample x{};
        for (int k = 0; std::getline(ss, cell, ','); ++k) {
            if (k == ia) x.i_a = std::stod(cell);
            if (k == ib) x.i_b = std::stod(cell);
            if (k == va) x.v_a = std::stod(cell);
            if (k == vb) x.v_b = std::stod(cell);
        }
        out.push_back(x);
    }
    return out;
}

}  // namespace

int main(int argc, char** argv)
{
    if (argc != 4) {
        std::fprintf(stderr, "usage: %s SCENARIO.toml CURRENTS.csv OUT.csv\n", argv[0]);
        return 2;
    }
    try {
        mcsim::Scenario sc = mcsim::load_scenario(argv[1]);
        const mcsim::HostDrive* host = mcsim::host_drive_find(sc.drive_kind);
        if (host == nullptr || host->set_applied_voltage == nullptr) {
            throw std::runtime_error(sc.path + ": the " + sc.drive_kind +
                                     " drive cannot be replayed open loop (its host part has no set_applied_voltage)");
        }
        auto storage = std::make_unique<drive_storage_t>();
        auto cfg = std::make_unique<drive_config_storage_t>();
        drive_t drive = mcsim::design_scenario_drive(sc, storage.get(), cfg.get());
        if (sc.motor.n_phases() != 2) {
            throw std::runtime_error(sc.path + ": a replay of a two-phase run (its motor has " +
                                     std::to_string(sc.motor.n_phases()) + " phases)");
        }
        const auto currents = read_currents(argv[2]);
        const std::string tmp = std::string(argv[3]) + ".tmp";
        std::FILE* f = std::fopen(tmp.c_str(), "w");
        if (f == nullptr) {
            throw std::runtime_error(std::string(argv[3]) + ": cannot write");
        }
        std::fprintf(f, "t_s,mode,theta_est,omega_est,v_a,v_b\n");
        const double dly = sc.compute_delay_samples;
        for (std::size_t k = 0; k < currents.size(); ++k) {
            // the observer sees the voltages the recorded run applied, so the
            // recorded currents stay consistent with them: with a computation
            // delay d, the recorded command of the last sample for d Ts, then
            // this one's (the mean over the sample, as the drive forms it)
            const Sample& now = currents[k];
            const Sample prev = k > 0 ? currents[k - 1] : Sample{};
            const double v_app[2] = {dly > 0.0 ? (1.0 - dly) * now.v_a + dly * prev.v_a : now.v_a,
                                     dly > 0.0 ? (1.0 - dly) * now.v_b + dly * prev.v_b : now.v_b};
            host->set_applied_voltage(&drive, v_app, 2);
            hal_sample_t in{};
            in.n_phases = 2;
            in.i_A[0] = mcsim::to_mc(currents[k].i_a);
            in.i_A[1] = mcsim::to_mc(currents[k].i_b);
            in.tick = static_cast<std::uint32_t>(k);
            hal_command_t out{};
            (void)drive_step(&drive, &in, &out);
            const mc_t va = out.v_V[0], vb = out.v_V[1];
            drive_status_t st{};
            drive_status(&drive, &st);
            std::fprintf(f, "%.6f,%d,%.9g,%.9g,%.9g,%.9g\n", sc.t_start_s() + static_cast<double>(k) * sc.ts_s, static_cast<int>(st.mode),
                         mcsim::to_double(st.theta_est_rad), mcsim::to_double(st.omega_est_rad_s),
                         mcsim::to_double(va), mcsim::to_double(vb));
        }
        // a write error (e.g. a full disk) must not rename a truncated file into place
        const bool written = std::ferror(f) == 0;
        if (std::fclose(f) != 0 || !written) {
            std::remove(tmp.c_str());
            throw std::runtime_error(std::string(argv[3]) + ": write failed");
        }
        if (std::rename(tmp.c_str(), argv[3]) != 0) {
            throw std::runtime_error(std::string(argv[3]) + ": cannot rename");
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
