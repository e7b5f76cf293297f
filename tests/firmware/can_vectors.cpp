// can_vectors: the firmware's CAN codec (firmware/comm/can_link.h) as a
// command-line filter, so tests/tools/test_can_contract.py can check it
// against cantools and the DBC (tools/can/drive.dbc).
//
//   can_vectors tlm    one line per telemetry frame packed from test values:
//                      "<message> <value> <id> <dlc> <hex data>", <value> the
//                      SI value every mc_t field of can_telemetry_t was set to
//   can_vectors cmd    reads "<id> <dlc> <hex data>" lines, prints per line
//                      "ok <kind> <theta_to> <duration> <omega_ref> <ramp>
//                      <omega_lim> <enable> <message> <period>" or
//                      "reject <can_reject_t>"
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>

#include "comm/can_link.h"
#include "math/mc_convert.h"

namespace {

const char* const kNames[CAN_TLM_COUNT] = {"Heartbeat", "Position", "Velocity", "Currents",
                                          "Observer",  "Voltages", "Timing",   "Version"};

int tlm()
{
    // zero, small and large of both signs, each signal's range edges and
    // beyond them (saturation), within what Q14.17 can hold
    const double values[] = {0.0,     0.001,   -0.001,  1.2345,   -1.2345,  3.2767,  -3.2768, 32.767,
                             -32.768, 65.534,  -65.536, 100.0,    -100.0,   327.67,  -327.68, 655.35,
                             1000.0,  -1000.0, 5000.0,  -5000.0,  16000.0,  -16000.0};
    for (double v : values) {
        can_telemetry_t t;
        std::memset(&t, 0, sizeof t);
        const mc_t x = mc_from_double(v);
        t.drive.theta_ref_rad = t.drive.theta_est_rad = x;
        t.drive.omega_ref_rad_s = t.drive.omega_est_rad_s = t.drive.accel_est_rad_s2 = t.drive.load_est_Nm = x;
        t.drive.i1_A = t.drive.i2_A = t.drive.i1_ref_A = t.drive.i2_ref_A = t.drive.i1_est_A = t.drive.i2_est_A = x;
        t.drive.emf1_V = t.drive.emf2_V = t.drive.v1_V = t.drive.v2_V = t.v_bus_V = x;
        t.step_time_us = x;
        // the integer signals, at fixed test values
        t.drive_kind = 1;
        t.drive.mode = 2;
        t.drive.state = 4;
        t.drive.enabled = true;
        t.drive.fault_code = 5;
        t.drive.fault_events = 7;
        t.rejected_commands = 9;
        t.counter = 65535;
        t.drive.saturated = true;
        t.drive.overruns = 1234;
        t.drive.relocks = 3;
        t.drive.first_fault = 11;
        t.excess_steps = 4321;
        t.config_source = 4;
        t.params_refused = true;
        for (int m = 0; m < CAN_TLM_COUNT; ++m) {
            can_frame_t f;
            if (!can_link_pack(static_cast<can_tlm_msg_t>(m), 3, &t, &f)) {
                std::fprintf(stderr, "can_vectors: pack %s failed\n", kNames[m]);
                return 1;
            }
            std::printf("%s %.9g %" PRIu32 " %u ", kNames[m], mc_to_double(x), f.id, f.dlc);
            for (int k = 0; k < f.dlc; ++k) std::printf("%02x", f.data[k]);
            std::printf("\n");
        }
    }
    return 0;
}

int cmd()
{
    std::string line;
    while (std::getline(std::cin, line)) {
        std::istringstream in(line);
        unsigned long id = 0, dlc = 0;
        std::string hex;
        in >> id >> dlc >> hex;
        can_frame_t f;
        std::memset(&f, 0, sizeof f);
        f.id = static_cast<uint32_t>(id);
        f.dlc = static_cast<uint8_t>(dlc);
        for (std::size_t k = 0; k + 1 < hex.size() && k / 2 < 8; k += 2) {
            f.data[k / 2] = static_cast<uint8_t>(std::stoul(hex.substr(k, 2), nullptr, 16));
        }
        can_cmd_t c;
        const can_reject_t r = can_link_parse(3, &f, &c);
        if (r != CAN_REJECT_NONE) {
            std::printf("reject %d\n", static_cast<int>(r));
            continue;
        }
        std::printf("ok %d %.9g %.9g %.9g %.9g %.9g %d %u %u\n", static_cast<int>(c.kind), mc_to_double(c.theta_to_rad),
                    mc_to_double(c.duration_s), mc_to_double(c.omega_ref_rad_s), mc_to_double(c.ramp_rad_s2),
                    mc_to_double(c.omega_lim_rad_s), c.enable ? 1 : 0, c.message, c.period_ms);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv)
{
    if (argc == 2 && std::strcmp(argv[1], "tlm") == 0) return tlm();
    if (argc == 2 && std::strcmp(argv[1], "cmd") == 0) return cmd();
    std::fprintf(stderr, "usage: can_vectors tlm|cmd\n");
    return 2;
}
