// plant_replay - held phase voltages through our plant (sim/model/pm_plant)
// at a prescribed speed: the side of the cross-check against
// gym-electric-motor that is ours (tools/crosscheck/crosscheck_pmsm.py),
// and our plant alone in tools/bench/sim_speed.py.
//
//   plant_replay --motor FILE.toml --in V.csv --out I.csv --omega W --ts TS
//                [--theta0-e RAD]
//   plant_replay --motor FILE.toml --in VW.csv --out I.csv --ts TS [--theta0-e RAD]
//
// V.csv: header v_a_V,v_b_V,v_c_V (leg voltages about the bus midpoint),
// row k held over [k Ts, (k+1) Ts), at the constant speed --omega. VW.csv:
// header v_a_V,v_b_V,v_c_V,omega_rad_s, the speed of row k set at k Ts and
// held over the row (a speed trajectory, e.g. a closed-loop run's, given as
// each sample's mean speed so the angle follows the run's; then no --omega). I.csv: t_s,i_a_A,i_b_A,i_c_A at k Ts, before row k is applied
// (row 0: zero current). The speed is held by an inertia of 1e30 kg m^2 (the
// torque changes it by < 1e-29 rad/s per sample). Bad input: one line on
// stderr, exit 2, nothing written.
#include <chrono>
#include <array>
#include <vector>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

#include "model/pm_plant.h"
#include "scenario/scenario.h"

namespace {

// Rows of v_a_V, v_b_V, v_c_V and, with the fourth column, omega_rad_s
// (*with_speed tells which header it was).
std::vector<std::array<double, 4>> read_voltages(const std::string& path, bool* with_speed)
{
    std::ifstream f(path);
    if (!f) {
        throw std::invalid_argument(path + ": cannot open");
    }
    std::string line;
    std::getline(f, line);
    if (!line.empty() && line.back() == '\r') {
        line.pop_back();
    }
    if (line == "v_a_V,v_b_V,v_c_V,omega_rad_s") {
        *with_speed = true;
    } else if (line == "v_a_V,v_b_V,v_c_V") {
        *with_speed = false;
    } else {
        throw std::invalid_argument(path + ": header must be v_a_V,v_b_V,v_c_V or v_a_V,v_b_V,v_c_V,omega_rad_s");
    }
    const int n_cols = *with_speed ? 4 : 3;
    std::vector<std::array<double, 4>> v;
    int row = 1;
    while (std::getline(f, line)) {
        ++row;
        if (line.empty()) {
            continue;
        }
        std::array<double, 4> x{};
        std::stringstream ss(line);
        for (int k = 0; k < n_cols; ++k) {
            std::string cell;
            if (!std::getline(ss, cell, ',')) {
                throw std::invalid_argument(path + ":" + std::to_string(row) + ": expected " +
                                            std::to_string(n_cols) + " values");
            }
            char* end = nullptr;
            x[k] = std::strtod(cell.c_str(), &end);
            if (end == cell.c_str() || !std::isfinite(x[k])) {
                // NOLINTNEXTLINE(performance-inefficient-string-concatenation): error path, once, then throws
                throw std::invalid_argument(path + ":" + std::to_string(row) + ": not a finite number: '" + cell + "'");
            }
        }
        v.push_back(x);
    }
    return v;
}

}  // namespace

// Outside its try blocks only the CLI11 set-up can throw (bad_alloc, or a
// duplicate option: a programming error every test run would show):
// std::terminate with the exception's message is the right end for those.
// NOLINTNEXTLINE(bugprone-exception-escape)
int main(int argc, char** argv)
{
    CLI::App app{"plant_replay: held phase voltages through the PMSM plant at a prescribed speed", "plant_replay"};
    std::string motor, in, out;
    double omega = 0.0, ts = 0.0, theta0_e = 0.0;
    app.add_option("--motor", motor, "motor file (sim/motors/*.toml)")->required();
    app.add_option("--in", in, "CSV v_a_V,v_b_V,v_c_V (then --omega), or v_a_V,v_b_V,v_c_V,omega_rad_s")->required();
    app.add_option("--out", out, "CSV to write: t_s,i_a_A,i_b_A,i_c_A")->required();
    CLI::Option* omega_opt = app.add_option("--omega", omega, "constant mechanical speed [rad/s]");
    app.add_option("--ts", ts, "hold time of a row [s]")->required();
    app.add_option("--theta0-e", theta0_e, "initial electrical angle [rad]");
    bool timing = false;
    app.add_flag("--timing", timing,
                 "print {\"loop_s\": ..., \"samples\": ...} on stdout: the wall time of the integration loop alone "
                 "(no file I/O, no formatting), for tools/bench/sim_speed.py");
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
    try {
        if (!(ts > 0.0) || !std::isfinite(omega) || !std::isfinite(theta0_e)) {
            throw std::invalid_argument("--ts must be > 0, --omega and --theta0-e finite");
        }
        mcsim::MotorParams m = mcsim::load_motor_file(motor);
        m.J_kgm2 = 1e30;
        m.fv_Nms_per_rad = 0.0;
        m.coulomb_Nm = 0.0;
        bool with_speed = false;
        const auto v = read_voltages(in, &with_speed);
        if (with_speed && omega_opt->count() > 0) {
            throw std::invalid_argument("--omega: " + in + " has an omega_rad_s column; give one speed, not both");
        }
        if (!with_speed && omega_opt->count() == 0) {
            throw std::invalid_argument("--omega: required when " + in + " has no omega_rad_s column");
        }
        if (with_speed && !v.empty()) {
            omega = v[0][3];
        }
        mcsim::PmPlant plant(m, mcsim::LoadProfile(), mcsim::PmPlant::kDefaultSubsteps);
        mcsim::PmPlant::State x0 = mcsim::PmPlant::State::Zero();
        x0[mcsim::PmPlant::kOmega] = omega;
        x0[mcsim::PmPlant::kTheta] = theta0_e / static_cast<double>(m.n_p);
        plant.reset(x0, 0.0);
        // the loop alone, timed; the currents are formatted afterwards
        std::vector<std::array<double, 3>> cur(v.size());
        const auto t0 = std::chrono::steady_clock::now();
        if (with_speed) {
            for (std::size_t k = 0; k < v.size(); ++k) {
                plant.phase_currents(cur[k].data());
                plant.set_speed(v[k][3]);
                plant.step_phases(v[k].data(), ts);
            }
        } else {
            for (std::size_t k = 0; k < v.size(); ++k) {
                plant.phase_currents(cur[k].data());
                plant.step_phases(v[k].data(), ts);
            }
        }
        const double loop_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::ostringstream os;
        os.precision(17);
        os << "t_s,i_a_A,i_b_A,i_c_A\n";
        for (std::size_t k = 0; k < v.size(); ++k) {
            os << static_cast<double>(k) * ts << ',' << cur[k][0] << ',' << cur[k][1] << ',' << cur[k][2] << '\n';
        }
        if (timing) {
            std::printf("{\"loop_s\": %.9g, \"samples\": %zu}\n", loop_s, v.size());
        }
        const std::string tmp = out + ".tmp";
        {
            std::ofstream f(tmp);
            f << os.str();
            if (!f) {
                throw std::runtime_error(out + ": write failed");
            }
        }
        if (std::rename(tmp.c_str(), out.c_str()) != 0) {
            std::remove(tmp.c_str());
            throw std::runtime_error(out + ": cannot rename into place");
        }
    } catch (const mcsim::ScenarioError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
