#include "comm/can_link.h"

#include "comm/generated/drive_can.h"
#include "mc_version.h"

/* Identifiers of node 0 (the DBC's) are multiples of 16; a node's id adds
 * its number, so the low four bits are the node and the rest the message. */
#define CAN_LINK_NODE_MASK 0xFu
#define CAN_LINK_CMD_FIRST 0x200u /* the command space: 0x200-0x2FF */
#define CAN_LINK_CMD_LAST 0x2FFu
/* ThetaTo's largest magnitude in Q14.17, in the DBC's 1e-5 rad: 16383 rad */
#define CAN_LINK_THETA_RAW_MAX ((int32_t)16383 * 100000)

_Static_assert(DRIVE_CAN_CMD_STOP_LENGTH == DRIVE_CAN_CMD_CLEAR_FAULTS_LENGTH,
               "CmdStop and CmdClearFaults are parsed alike (one reserved byte)");

const char *can_link_reject_name(can_reject_t r)
{
    switch (r) {
    case CAN_REJECT_NONE: return "none";
    case CAN_REJECT_NOT_OURS: return "not ours";
    case CAN_REJECT_UNKNOWN_ID: return "unknown id";
    case CAN_REJECT_DLC: return "dlc";
    case CAN_REJECT_RANGE: return "range";
    case CAN_REJECT_MODE: return "mode";
    default: return "?";
    }
}

int64_t can_link_to_raw(mc_t x, int32_t inv, int64_t lo, int64_t hi)
{
    if (!mc_is_finite(x)) {
        return 0;
    }
#if MC_FIXED
    /* x = raw 2^-17: x inv = raw inv 2^-17, |raw inv| < 2^31 2^17 */
    const int64_t p = (int64_t)mc_raw(x) * (int64_t)inv;
    int64_t r = (p + ((int64_t)1 << (MC_FRAC_BITS - 1))) >> MC_FRAC_BITS; /* round half up */
#else
    const float y = mc_mul(x, (float)inv);
    /* beyond +-2^62 the conversion is undefined: saturate first */
    if (!(y < 4.0e18f)) {
        return hi;
    }
    if (!(y > -4.0e18f)) {
        return lo;
    }
    int64_t r = (int64_t)(y >= 0.0f ? y + 0.5f : y - 0.5f);
#endif
    return r < lo ? lo : (r > hi ? hi : r);
}

mc_t can_link_from_raw(int64_t r, int32_t inv)
{
#if MC_FIXED
    /* r / inv in Q14.17: (r 2^17 + inv/2) / inv, saturated; |r| < 2^32 here */
    const int64_t num = r * (int64_t)MC_ONE_RAW;
    const int64_t q = (num >= 0 ? num + inv / 2 : num - inv / 2) / inv;
    return mc_from_raw(q > INT32_MAX ? INT32_MAX : (q < -INT32_MAX ? -INT32_MAX : (int32_t)q));
#else
    return (float)r / (float)inv;
#endif
}

#define I16(x, inv) ((int16_t)can_link_to_raw((x), (inv), INT16_MIN, INT16_MAX))
#define U16(x, inv) ((uint16_t)can_link_to_raw((x), (inv), 0, UINT16_MAX))
#define I32(x, inv) ((int32_t)can_link_to_raw((x), (inv), INT32_MIN, INT32_MAX))

bool can_link_pack(can_tlm_msg_t m, uint8_t node, const can_telemetry_t *t, can_frame_t *f)
{
    if (node > CAN_LINK_NODE_MAX) {
        return false;
    }
    int n = -1;
    uint32_t id = 0;
    switch (m) {
    case CAN_TLM_HEARTBEAT: {
        struct drive_can_heartbeat_t s = {0};
        s.drive_kind = (uint8_t)(t->drive_kind & 0xFu);
        s.mode = (uint8_t)(t->drive.mode & 0x3u);
        s.enabled = t->drive.enabled ? 1u : 0u;
        s.state = (uint8_t)(t->drive.state & 0xFu);
        s.msg_set_version = (uint8_t)CAN_LINK_MSG_SET_VERSION;
        s.fault_code = t->drive.fault_code;
        s.fault_events = t->drive.fault_events;
        s.rejected_commands = t->rejected_commands;
        s.counter = t->counter;
        s.config_source = (uint8_t)(t->config_source & 0x7u);
        s.params_refused = t->params_refused ? 1u : 0u;
        id = DRIVE_CAN_HEARTBEAT_FRAME_ID;
        n = drive_can_heartbeat_pack(f->data, &s, sizeof f->data);
        break;
    }
    case CAN_TLM_POSITION: {
        struct drive_can_position_t s = {0};
        s.theta_ref = I32(t->drive.theta_ref_rad, 100000);
        s.theta_est = I32(t->drive.theta_est_rad, 100000);
        id = DRIVE_CAN_POSITION_FRAME_ID;
        n = drive_can_position_pack(f->data, &s, sizeof f->data);
        break;
    }
    case CAN_TLM_VELOCITY: {
        struct drive_can_velocity_t s = {0};
        s.omega_ref = I16(t->drive.omega_ref_rad_s, 100);
        s.omega_est = I16(t->drive.omega_est_rad_s, 100);
        s.accel_est = I16(t->drive.accel_est_rad_s2, 1);
        s.load_est = I16(t->drive.load_est_Nm, 10000);
        id = DRIVE_CAN_VELOCITY_FRAME_ID;
        n = drive_can_velocity_pack(f->data, &s, sizeof f->data);
        break;
    }
    case CAN_TLM_CURRENTS: {
        struct drive_can_currents_t s = {0};
        s.i1 = I16(t->drive.i1_A, 1000);
        s.i2 = I16(t->drive.i2_A, 1000);
        s.i1_ref = I16(t->drive.i1_ref_A, 1000);
        s.i2_ref = I16(t->drive.i2_ref_A, 1000);
        id = DRIVE_CAN_CURRENTS_FRAME_ID;
        n = drive_can_currents_pack(f->data, &s, sizeof f->data);
        break;
    }
    case CAN_TLM_OBSERVER: {
        struct drive_can_observer_t s = {0};
        s.i1_est = I16(t->drive.i1_est_A, 1000);
        s.i2_est = I16(t->drive.i2_est_A, 1000);
        s.emf1 = I16(t->drive.emf1_V, 500);
        s.emf2 = I16(t->drive.emf2_V, 500);
        id = DRIVE_CAN_OBSERVER_FRAME_ID;
        n = drive_can_observer_pack(f->data, &s, sizeof f->data);
        break;
    }
    case CAN_TLM_VOLTAGES: {
        struct drive_can_voltages_t s = {0};
        s.v1 = I16(t->drive.v1_V, 500);
        s.v2 = I16(t->drive.v2_V, 500);
        s.v_bus = U16(t->v_bus_V, 100);
        s.saturated = t->drive.saturated ? 1u : 0u;
        id = DRIVE_CAN_VOLTAGES_FRAME_ID;
        n = drive_can_voltages_pack(f->data, &s, sizeof f->data);
        break;
    }
    case CAN_TLM_TIMING: {
        struct drive_can_timing_t s = {0};
        s.step_time = U16(t->step_time_us, 100);
        s.overruns = t->drive.overruns;
        s.relocks = t->drive.relocks;
        s.first_fault = t->drive.first_fault;
        s.excess_steps = t->excess_steps;
        id = DRIVE_CAN_TIMING_FRAME_ID;
        n = drive_can_timing_pack(f->data, &s, sizeof f->data);
        break;
    }
    case CAN_TLM_VERSION: {
        struct drive_can_version_t s = {0};
        s.fw_major = (uint8_t)MC_VERSION_MAJOR;
        s.fw_minor = (uint8_t)MC_VERSION_MINOR;
        s.fw_patch = (uint8_t)MC_VERSION_PATCH;
        s.fixed_point = MC_FIXED ? 1u : 0u;
        id = DRIVE_CAN_VERSION_FRAME_ID;
        n = drive_can_version_pack(f->data, &s, sizeof f->data);
        break;
    }
    default:
        return false;
    }
    if (n < 0) {
        return false;
    }
    f->id = id + node;
    f->dlc = (uint8_t)n;
    return true;
}

void can_link_pack_param_reply(uint8_t node, uint8_t op, uint8_t status, uint8_t seq, uint16_t id, uint32_t value,
                               can_frame_t *f)
{
    struct drive_can_param_reply_t s;
    (void)drive_can_param_reply_init(&s);
    s.op = (uint8_t)(op & 0x0Fu);
    s.status = (uint8_t)(status & 0x0Fu);
    s.seq = seq;
    s.param_id = id;
    s.value = (int32_t)value;
    f->id = DRIVE_CAN_PARAM_REPLY_FRAME_ID + node;
    f->dlc = DRIVE_CAN_PARAM_REPLY_LENGTH;
    (void)drive_can_param_reply_pack(f->data, &s, sizeof(f->data));
}

can_reject_t can_link_parse(uint8_t node, const can_frame_t *f, can_cmd_t *cmd)
{
    cmd->kind = CAN_CMD_NONE;
    if (f->id > 0x7FFu || (f->id & CAN_LINK_NODE_MASK) != node || f->id < CAN_LINK_CMD_FIRST ||
        f->id > CAN_LINK_CMD_LAST) {
        return CAN_REJECT_NOT_OURS;
    }
    if (f->dlc > 8u) {
        return CAN_REJECT_DLC;
    }
    const uint32_t base = f->id & ~(uint32_t)CAN_LINK_NODE_MASK;
    can_cmd_t c = {0};
    switch (base) {
    case DRIVE_CAN_CMD_ENABLE_FRAME_ID: {
        struct drive_can_cmd_enable_t s;
        if (f->dlc != DRIVE_CAN_CMD_ENABLE_LENGTH || drive_can_cmd_enable_unpack(&s, f->data, f->dlc) != 0) {
            return CAN_REJECT_DLC;
        }
        if (!drive_can_cmd_enable_enable_is_in_range(s.enable) || (f->data[0] & 0xFEu) != 0u) {
            return CAN_REJECT_RANGE; /* the unused bits must be 0 */
        }
        c.kind = CAN_CMD_ENABLE;
        c.enable = s.enable != 0u;
        break;
    }
    case DRIVE_CAN_CMD_MOVE_FRAME_ID: {
        struct drive_can_cmd_move_t s;
        if (f->dlc != DRIVE_CAN_CMD_MOVE_LENGTH || drive_can_cmd_move_unpack(&s, f->data, f->dlc) != 0) {
            return CAN_REJECT_DLC;
        }
        if (!drive_can_cmd_move_theta_to_is_in_range(s.theta_to) || !drive_can_cmd_move_duration_is_in_range(s.duration)) {
            return CAN_REJECT_RANGE;
        }
#if MC_FIXED
        /* a target the fixed-point firmware cannot hold (Q14.17: +-16384
         * rad) is refused, not saturated */
        if (s.theta_to > CAN_LINK_THETA_RAW_MAX || s.theta_to < -CAN_LINK_THETA_RAW_MAX) {
            return CAN_REJECT_RANGE;
        }
#endif
        c.kind = CAN_CMD_MOVE;
        c.theta_to_rad = can_link_from_raw(s.theta_to, 100000);
        c.duration_s = can_link_from_raw(s.duration, 1000);
        break;
    }
    case DRIVE_CAN_CMD_SPEED_FRAME_ID: {
        struct drive_can_cmd_speed_t s;
        if (f->dlc != DRIVE_CAN_CMD_SPEED_LENGTH || drive_can_cmd_speed_unpack(&s, f->data, f->dlc) != 0) {
            return CAN_REJECT_DLC;
        }
        if (!drive_can_cmd_speed_omega_ref_is_in_range(s.omega_ref) || !drive_can_cmd_speed_ramp_is_in_range(s.ramp)) {
            return CAN_REJECT_RANGE;
        }
        c.kind = CAN_CMD_SPEED;
        c.omega_ref_rad_s = can_link_from_raw(s.omega_ref, 100);
        c.ramp_rad_s2 = can_link_from_raw(s.ramp, 10);
        break;
    }
    case DRIVE_CAN_CMD_STOP_FRAME_ID:
    case DRIVE_CAN_CMD_CLEAR_FAULTS_FRAME_ID: {
        /* one reserved byte, 0 */
        if (f->dlc != DRIVE_CAN_CMD_STOP_LENGTH) {
            return CAN_REJECT_DLC;
        }
        if (f->data[0] != 0u) {
            return CAN_REJECT_RANGE;
        }
        c.kind = (base == DRIVE_CAN_CMD_STOP_FRAME_ID) ? CAN_CMD_STOP : CAN_CMD_CLEAR_FAULTS;
        break;
    }
    case DRIVE_CAN_CMD_SET_OMEGA_LIM_FRAME_ID: {
        struct drive_can_cmd_set_omega_lim_t s;
        if (f->dlc != DRIVE_CAN_CMD_SET_OMEGA_LIM_LENGTH ||
            drive_can_cmd_set_omega_lim_unpack(&s, f->data, f->dlc) != 0) {
            return CAN_REJECT_DLC;
        }
        if (!drive_can_cmd_set_omega_lim_omega_lim_is_in_range(s.omega_lim)) {
            return CAN_REJECT_RANGE;
        }
        c.kind = CAN_CMD_SET_OMEGA_LIM;
        c.omega_lim_rad_s = can_link_from_raw(s.omega_lim, 1000);
        break;
    }
    case DRIVE_CAN_CMD_SET_RATE_FRAME_ID: {
        struct drive_can_cmd_set_rate_t s;
        if (f->dlc != DRIVE_CAN_CMD_SET_RATE_LENGTH || drive_can_cmd_set_rate_unpack(&s, f->data, f->dlc) != 0) {
            return CAN_REJECT_DLC;
        }
        if (!drive_can_cmd_set_rate_message_is_in_range(s.message) || !drive_can_cmd_set_rate_period_is_in_range(s.period)) {
            return CAN_REJECT_RANGE;
        }
        c.kind = CAN_CMD_SET_RATE;
        c.message = s.message;
        c.period_ms = s.period;
        break;
    }
    case DRIVE_CAN_PARAM_REQUEST_FRAME_ID: {
        struct drive_can_param_request_t s;
        if (f->dlc != DRIVE_CAN_PARAM_REQUEST_LENGTH || drive_can_param_request_unpack(&s, f->data, f->dlc) != 0) {
            return CAN_REJECT_DLC;
        }
        if ((f->data[0] & 0xF0u) != 0u) {
            return CAN_REJECT_RANGE; /* bits 4-7 unused: 0 */
        }
        c.kind = CAN_CMD_PARAM;
        c.param_op = s.op;
        c.param_seq = s.seq;
        c.param_id = s.param_id;
        c.param_value = (uint32_t)s.value;
        break;
    }
    default:
        return CAN_REJECT_UNKNOWN_ID;
    }
    *cmd = c;
    return CAN_REJECT_NONE;
}
