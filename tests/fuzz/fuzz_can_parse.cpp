// libFuzzer target: the CAN command parser (firmware/comm/can_link.h) on
// arbitrary frames. Input bytes: [0..1] identifier (11 bits used, the rest
// kept so ids beyond 0x7FF come too), [2] DLC (any value, also > 8), [3]
// the node the parser is for, [4..11] data; a longer input is a burst of
// such frames. Checked for every frame: no crash or sanitizer report; a
// refused frame yields CAN_CMD_NONE and a known reason; an accepted one is
// a command of our node, in the command space, with the DBC's length and
// in-range fields (a ParamRequest's signals as the frame carries them); parsing twice gives the same answer (the parser keeps no
// state: a bad frame cannot change anything).
//
// Then the same frame reaches a drive's node (comm/can_node.h) on node 0:
// the paper-000 position drive in the middle of its move and the paper-001
// speed drive in its start; a frame the node refuses (any reason) leaves
// every byte of the drive as it was and is counted once (ignored when not
// ours); after each frame the drive takes one sample and its voltages stay
// finite and within the supply, whatever the commands before did.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "comm/can_link.h"
#include "comm/can_node.h"
#include "drives/registry.h"
#include "comm/generated/drive_can.h"
#include "design/paper000_design.h"
#include "design/paper001_design.h"
#include "math/mc_convert.h"

namespace {
void check(bool ok)
{
    if (!ok) std::abort();
}

hal_sample_t sample(int n_phases, uint32_t k)
{
    hal_sample_t in{};
    in.n_phases = static_cast<uint8_t>(n_phases);
    in.tick = k;
    in.i_A[0] = mc_from_double(1e-3 * std::sin(0.1 * k));
    in.i_A[1] = mc_from_double(1e-3 * std::cos(0.1 * k));
    if (n_phases == 3) in.i_A[2] = mc_from_double(-1e-3 * (std::sin(0.1 * k) + std::cos(0.1 * k)));
    in.v_bus_V = mc_from_double(n_phases == 3 ? 48.0 : 30.0);
    return in;
}

// The two drives, designed once and stepped into their runs (position:
// 0.2 s into a 0 -> 18 rad move over 2 s; speed: 0.1 s into its start).
struct Drives {
    paper000_drive_t pos{};
    paper001_drive_t speed{};
    Drives()
    {
        drive_design_input_t in;
        drive_design_defaults(&in);
        in.motor = {9e-3, 3.01, 0.27, 3.18e-4, 2.37e-3, 50, 0.0752, 2, 9e-3};
        in.ts_s = 1e-4;
        in.v_max_V = 30.0;
        in.i_max_A = 3.0;
        in.i_trip_A = 4.5;
        in.omega_lim_rad_s = 3.0;
        in.n_segments = 1;
        in.segments[0] = {0.0, 2.0, 18.0};
        in.align_rotor = 0;
        paper000_config_t cfg;
        char err[160];
        check(drive_design(&in, &cfg, err, sizeof err) && paper000_drive_init(&pos, &cfg));
        p001_design_input_t sp;
        p001_design_defaults(&sp);
        sp.motor = motor_design_input_t{};  // paper 001's PMSM (design/motor_design.h)
        sp.motor.n_phases = 3;
        sp.motor.R_ohm = 0.225;
        sp.motor.L_H = sp.motor.L_q_H = 3.8e-3;
        sp.motor.n_p = 3;
        sp.motor.K_Nm_per_A = 3 * 0.17;
        sp.motor.J_kgm2 = 0.012;
        sp.ts_s = 1e-4;
        sp.i_max_A = 8.0;
        sp.i_trip_A = 12.0;
        sp.n_points = 2;
        sp.t_s[0] = 0.0;
        sp.omega_rad_s[0] = 0.0;
        sp.t_s[1] = 1.0;
        sp.omega_rad_s[1] = 5.0;
        paper001_config_t scfg;
        p001_design_report_t rep;
        check(p001_design(&sp, &scfg, &rep, err, sizeof err) && paper001_drive_init(&speed, &scfg));
        hal_command_t out;
        for (uint32_t k = 0; k < 2000; ++k) {
            hal_sample_t a = sample(2, k);
            (void)paper000_drive_step(&pos, &a, &out);
        }
        for (uint32_t k = 0; k < 1000; ++k) {
            hal_sample_t b = sample(3, k);
            (void)paper001_drive_step(&speed, &b, &out);
        }
    }
};

void through_node(can_node_t* n, drive_t* d, const can_frame_t& f, uint32_t tick, int n_phases, double v_lim)
{
    const size_t bytes = d->ops->state_bytes;
    std::vector<uint8_t> before(bytes);
    std::memcpy(before.data(), d->self, bytes);
    const uint32_t rej0 = n->rejected, ign0 = n->ignored, acc0 = n->accepted;
    const can_reject_t r = can_node_receive(n, tick, &f, &can_node_apply_drive, d);
    if (r == CAN_REJECT_NOT_OURS) {
        check(n->ignored == ign0 + 1u && n->rejected == rej0 && n->accepted == acc0);
    } else if (r != CAN_REJECT_NONE) {
        check(n->rejected == rej0 + 1u && n->accepted == acc0 && n->last_reject == r);
    } else {
        check(n->accepted == acc0 + 1u && n->rejected == rej0);
    }
    if (r != CAN_REJECT_NONE) {
        check(std::memcmp(before.data(), d->self, bytes) == 0);
    }
    hal_sample_t in = sample(n_phases, tick);
    hal_command_t out;
    (void)drive_step(d, &in, &out);
    for (int k = 0; k < n_phases; ++k) {
        const double v = mc_to_double(out.v_V[k]);
        check(std::isfinite(v) && std::fabs(v) <= v_lim);
    }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    static const Drives pristine;
    static Drives work;  // a copy per input: commands of one input do not leak into the next
    std::memcpy(&work.pos, &pristine.pos, sizeof work.pos);
    std::memcpy(&work.speed, &pristine.speed, sizeof work.speed);
    can_tx_config_t tc;
    can_tx_defaults(&tc, 0, 10000);
    can_node_t n_pos, n_speed;
    if (!can_node_init(&n_pos, &tc)) return 0;
    if (!can_node_init(&n_speed, &tc)) return 0;
    uint32_t tick = 2000;
    constexpr size_t kFrame = 12;
    for (size_t off = 0; off + 4 <= size; off += kFrame) {
        can_frame_t f;
        std::memset(&f, 0, sizeof f);
        f.id = static_cast<uint32_t>(data[off] | (data[off + 1] << 8));
        f.dlc = data[off + 2];
        const uint8_t node = static_cast<uint8_t>(data[off + 3] & 0x1Fu);  // also beyond 15
        const size_t n = (size - off - 4) < 8 ? (size - off - 4) : 8;
        std::memcpy(f.data, data + off + 4, n);
        can_cmd_t c1, c2;
        const can_reject_t r1 = can_link_parse(node, &f, &c1);
        const can_reject_t r2 = can_link_parse(node, &f, &c2);
        check(r1 == r2 && c1.kind == c2.kind);
        drive_t pos = {&paper000_drive_ops, &work.pos}, speed = {&paper001_drive_ops, &work.speed};
        through_node(&n_pos, &pos, f, tick, 2, 30.0);
        through_node(&n_speed, &speed, f, tick, 3, 24.0);
        ++tick;
        if (r1 != CAN_REJECT_NONE) {
            check(c1.kind == CAN_CMD_NONE);
            check(r1 == CAN_REJECT_NOT_OURS || r1 == CAN_REJECT_UNKNOWN_ID || r1 == CAN_REJECT_DLC ||
                  r1 == CAN_REJECT_RANGE);
            continue;
        }
        check(c1.kind != CAN_CMD_NONE);
        check((f.id & 0xFu) == node && f.id >= 0x200u && f.id <= 0x2FFu && f.dlc <= 8u);
        switch (c1.kind) {
        case CAN_CMD_MOVE:
            check(f.dlc == DRIVE_CAN_CMD_MOVE_LENGTH && mc_to_double(c1.duration_s) > 0.0);
            break;
        case CAN_CMD_SPEED:
            check(f.dlc == DRIVE_CAN_CMD_SPEED_LENGTH && mc_to_double(c1.ramp_rad_s2) > 0.0);
            break;
        case CAN_CMD_SET_OMEGA_LIM:
            check(f.dlc == DRIVE_CAN_CMD_SET_OMEGA_LIM_LENGTH && mc_to_double(c1.omega_lim_rad_s) > 0.0);
            break;
        case CAN_CMD_SET_RATE:
            check(f.dlc == DRIVE_CAN_CMD_SET_RATE_LENGTH && c1.message < CAN_TLM_COUNT && c1.period_ms <= 60000u);
            break;
        case CAN_CMD_ENABLE:
            check(f.dlc == DRIVE_CAN_CMD_ENABLE_LENGTH);
            break;
        case CAN_CMD_STOP:
        case CAN_CMD_CLEAR_FAULTS:
            check(f.dlc == 1u && f.data[0] == 0u);
            break;
        case CAN_CMD_PARAM:  // the signals as they travel (answered by the node's handler: none here)
            check(f.dlc == DRIVE_CAN_PARAM_REQUEST_LENGTH && (f.data[0] & 0xF0u) == 0u &&
                  c1.param_op == (f.data[0] & 0x0Fu) && c1.param_seq == f.data[1] &&
                  c1.param_id == static_cast<uint16_t>(f.data[2] | (f.data[3] << 8)) &&
                  c1.param_value == static_cast<uint32_t>(f.data[4] | (f.data[5] << 8) | (f.data[6] << 16) |
                                                          (static_cast<uint32_t>(f.data[7]) << 24)));
            break;
        default:
            check(false);
        }
    }
    return 0;
}
