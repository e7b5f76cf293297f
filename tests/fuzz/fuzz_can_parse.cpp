// libFuzzer target: the CAN command parser (firmware/comm/can_link.h) on
// arbitrary frames. Input bytes: [0..1] identifier (11 bits used, the rest
// kept so ids beyond 0x7FF come too), [2] DLC (any value, also > 8), [3]
// the node the parser is for, [4..11] data; a longer input is a burst of
// such frames. Checked for every frame: no crash or sanitizer report; a
// refused frame yields CAN_CMD_NONE and a known reason; an accepted one is
// a command of our node, in the command space, with the DBC's length and
// in-range fields; parsing twice gives the same answer (the parser keeps no
// state: a bad frame cannot change anything).
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "comm/can_link.h"
#include "comm/generated/drive_can.h"
#include "math/mc_convert.h"

namespace {
void check(bool ok)
{
    if (!ok) std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
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
        default:
            check(false);
        }
    }
    return 0;
}
