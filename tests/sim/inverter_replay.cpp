// inverter_replay - commanded leg voltages through our averaged inverter
// (sim/model/inverter.h) into our PMSM plant (sim/model/pm_plant.h) at a
// held speed: our side of the inverter cross-check against
// gym-electric-motor's interlocking-time converter
// (tools/crosscheck/crosscheck_inverter.py), the way sim/replay/plant_replay
// is our side of the plant's.
//
//   inverter_replay --motor FILE.toml --in V.csv --out I.csv --omega W --ts TS
//                   --vdc V [--dead-time-s T] [--f-pwm-hz F] [--i-transition-a I]
//                   [--ideal] [--timing]
//
// V.csv: header v_a_V,v_b_V,v_c_V, the commanded leg voltages about the bus
// midpoint, row k held over [k Ts, (k+1) Ts). Each row the inverter turns
// the command into the applied leg voltages with the leg currents at k Ts
// (the backend's rule, model/hal_sw_plant.cpp); the plant integrates them.
// I.csv: t_s,i_a_A,i_b_A,i_c_A,v_a_V,v_b_V,v_c_V: the currents at k Ts
// (before row k) and the voltages applied over row k. --f-pwm-hz defaults
// to 1/TS (one switching period per row). --ideal: no inverter, the
// amplifier's clamp to +-V/2. --timing: {"loop_s": ..., "samples": ...} on
// stdout (the loop alone). Bad input: one line on stderr, exit 2.
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "model/amplifier.h"
#include "model/inverter.h"
#include "model/pm_plant.h"
#include "scenario/scenario.h"

namespace {

std::vector<std::array<double, 3>> read_commands(const std::string& path)
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
    if (line != "v_a_V,v_b_V,v_c_V") {
        throw std::invalid_argument(path + ": header must be v_a_V,v_b_V,v_c_V");
    }
    std::vector<std::array<double, 3>> v;
    int row = 1;
    while (std::getline(f, line)) {
        ++row;
        if (line.empty()) {
            continue;
        }
        std::array<double, 3> x{};
        std::stringstream ss(line);
        for (double& xk : x) {
            std::string cell;
            if (!std::getline(ss, cell, ',')) {
                throw std::invalid_argument(path + ":" + std::to_string(row) + ": expected 3 values");
            }
            char* end = nullptr;
            xk = std::strtod(cell.c_str(), &end);
            if (end == cell.c_str() || !std::isfinite(xk)) {
                throw std::invalid_argument(path + ":" + std::to_string(row) + ": not a finite number");
            }
        }
        v.push_back(x);
    }
    return v;
}

}  // namespace

// NOLINTNEXTLINE(bugprone-exception-escape): as plant_replay's main
int main(int argc, char** argv)
{
    CLI::App app{"inverter_replay: commanded leg voltages through the averaged inverter into the PMSM plant",
                 "inverter_replay"};
    std::string motor, in, out;
    double omega = 0.0, ts = 0.0, vdc = 0.0, dead = 0.0, f_pwm = 0.0, i_tr = 0.0;
    bool ideal = false, timing = false;
    app.add_option("--motor", motor, "motor file (sim/motors/*.toml, pmsm3)")->required();
    app.add_option("--in", in, "CSV v_a_V,v_b_V,v_c_V: commanded leg voltages")->required();
    app.add_option("--out", out, "CSV to write: t_s,i_a_A,i_b_A,i_c_A,v_a_V,v_b_V,v_c_V")->required();
    app.add_option("--omega", omega, "held mechanical speed [rad/s]")->required();
    app.add_option("--ts", ts, "hold time of a row [s]")->required();
    app.add_option("--vdc", vdc, "DC link [V]")->required();
    app.add_option("--dead-time-s", dead, "dead time [s]");
    app.add_option("--f-pwm-hz", f_pwm, "PWM frequency [Hz] (default 1/ts)");
    app.add_option("--i-transition-a", i_tr, "the transition current i_tr [A] (0: hard sign)");
    app.add_flag("--ideal", ideal, "no inverter: the amplifier's clamp");
    app.add_flag("--timing", timing, "print the loop's wall time as JSON on stdout");
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
    try {
        if (!(ts > 0.0) || !(vdc > 0.0) || !std::isfinite(omega)) {
            throw std::invalid_argument("--ts and --vdc must be > 0, --omega finite");
        }
        mcsim::MotorParams m = mcsim::load_motor_file(motor);
        if (m.type != mcsim::MotorType::kPmsm3) {
            throw std::invalid_argument(motor + ": the replay needs a pmsm3 motor");
        }
        m.J_kgm2 = 1e30;  // the speed held (plant_replay's rule)
        m.fv_Nms_per_rad = 0.0;
        m.coulomb_Nm = 0.0;
        mcsim::InverterParams ip;
        ip.f_pwm_Hz = f_pwm > 0.0 ? f_pwm : 1.0 / ts;
        ip.dead_time_s = dead;
        ip.i_transition_A = i_tr;
        if (const char* why = ip.problem()) {
            throw std::invalid_argument(std::string("inverter: ") + why);
        }
        const mcsim::Inverter inv(ip);
        mcsim::Amplifier amp;
        amp.v_max_V = 0.5 * vdc;
        const auto cmd = read_commands(in);
        mcsim::PmPlant plant(m, mcsim::LoadProfile(), mcsim::PmPlant::kDefaultSubsteps);
        mcsim::PmPlant::State x0 = mcsim::PmPlant::State::Zero();
        x0[mcsim::PmPlant::kOmega] = omega;
        plant.reset(x0, 0.0);
        std::vector<std::array<double, 6>> rows(cmd.size());
        const auto t0 = std::chrono::steady_clock::now();
        for (std::size_t k = 0; k < cmd.size(); ++k) {
            double i[3];
            plant.phase_currents(i);
            double v[3];
            if (ideal) {
                for (int j = 0; j < 3; ++j) {
                    v[j] = amp.apply(cmd[k][j]);
                }
            } else {
                inv.apply(3, cmd[k].data(), i, vdc, v);
            }
            rows[k] = {i[0], i[1], i[2], v[0], v[1], v[2]};
            plant.step_phases(v, ts);
        }
        const double loop_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::ofstream f(out);
        f.precision(17);
        f << "t_s,i_a_A,i_b_A,i_c_A,v_a_V,v_b_V,v_c_V\n";
        for (std::size_t k = 0; k < rows.size(); ++k) {
            f << static_cast<double>(k) * ts;
            for (double x : rows[k]) {
                f << ',' << x;
            }
            f << '\n';
        }
        if (!f) {
            throw std::runtime_error(out + ": write failed");
        }
        if (timing) {
            std::printf("{\"loop_s\": %.9g, \"samples\": %zu}\n", loop_s, cmd.size());
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
