/*
 * can_link.h - the drives' CAN message set (tools/can/drive.dbc, the one
 * source) in firmware units: telemetry values in mc_t packed into frames,
 * command frames validated and turned into commands in mc_t. The bit
 * layout is the C that cantools generates from the DBC
 * (comm/generated/drive_can.{h,c}, regenerated and compared by ctest
 * tools.can_codegen; never edited by hand); this file adds the scaling
 * between SI values and the DBC's integers, in the firmware numeric type
 * (no float in the fixed-point build), and the validation of commands:
 * identifier, node, length (DLC), every signal's DBC range. A rejected
 * frame changes nothing and is counted. Nothing allocates; no I/O.
 */
#ifndef COMM_CAN_LINK_H
#define COMM_CAN_LINK_H

#include <stdbool.h>
#include <stdint.h>

#include "drives/drive.h"
#include "hal/hal_types.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

#define CAN_LINK_MSG_SET_VERSION 5u   /* the DBC's MsgSetVersion; VERSION "drive-can 5" (1 + Version + ExcessSteps + ParamRequest, ParamReply + ConfigSource, ParamsRefused) */
#define CAN_LINK_NODE_MAX 15u          /* node ids 0-15 are added to the DBC's (node 0) ids */

/* One classic CAN frame: the HAL's (hal/hal_types.h). */
typedef hal_can_frame_t can_frame_t;

/* Telemetry messages, in the order of CmdSetRate's Message signal. */
typedef enum {
    CAN_TLM_HEARTBEAT = 0,
    CAN_TLM_POSITION = 1,
    CAN_TLM_VELOCITY = 2,
    CAN_TLM_CURRENTS = 3,
    CAN_TLM_OBSERVER = 4,
    CAN_TLM_VOLTAGES = 5,
    CAN_TLM_TIMING = 6,
    CAN_TLM_VERSION = 7, /* the firmware's version (mc_version.h) and numeric type: constants */
    CAN_TLM_COUNT = 8
} can_tlm_msg_t;

/* Everything the telemetry carries, SI in mc_t (the DBC's comments say
 * what each is for each drive): the drive's status (drives/drive.h, the
 * one list of what a drive reports) and what the node and the backend add.
 * Out-of-range values saturate to the signal's range; a non-finite one is
 * sent as 0. */
typedef struct {
    drive_status_t drive;        /* mode, state, faults, estimates, currents, voltages */
    uint8_t drive_kind;          /* the DBC's DriveKind (the drive's operations) */
    uint8_t rejected_commands;   /* the node's */
    uint16_t counter;            /* the heartbeat's */
    mc_t v_bus_V, step_time_us;  /* the backend's */
    uint16_t excess_steps;       /* the step/dir input's (trajectory/step_shaper.h), wrapping; 0 without one */
    uint8_t config_source;       /* the heartbeat's ConfigSource (param_service_config_source), 0 without a store */
    bool params_refused;         /* the parameters do not design: CmdEnable refused */
} can_telemetry_t;

/* Packs telemetry message m of node into *f. Returns false for an unknown m
 * or node (f untouched). */
bool can_link_pack(can_tlm_msg_t m, uint8_t node, const can_telemetry_t *t, can_frame_t *f);

typedef enum {
    CAN_CMD_NONE = 0,
    CAN_CMD_ENABLE,
    CAN_CMD_MOVE,
    CAN_CMD_SPEED,
    CAN_CMD_STOP,
    CAN_CMD_SET_OMEGA_LIM,
    CAN_CMD_CLEAR_FAULTS,
    CAN_CMD_SET_RATE,
    CAN_CMD_PARAM /* ParamRequest: answered by the node's parameter handler (can_node.h) */
} can_cmd_kind_t;

/* A validated command, SI in mc_t. */
typedef struct {
    can_cmd_kind_t kind;
    bool enable;
    mc_t theta_to_rad, duration_s;
    mc_t omega_ref_rad_s, ramp_rad_s2;
    mc_t omega_lim_rad_s;
    uint8_t message;
    uint16_t period_ms;
    /* ParamRequest's signals as they travel (config/params.h reads them):
     * the op (0-15: an op the image does not know is answered
     * bad_request), the host's sequence number, the id, the 32 bits */
    uint8_t param_op, param_seq;
    uint16_t param_id;
    uint32_t param_value;
} can_cmd_t;

/* Why a frame was refused (0: accepted). */
typedef enum {
    CAN_REJECT_NONE = 0,
    CAN_REJECT_NOT_OURS,   /* another node's frame or a telemetry id: ignored, not counted */
    CAN_REJECT_UNKNOWN_ID, /* in our node's command space but no command */
    CAN_REJECT_DLC,        /* length differs from the DBC's */
    CAN_REJECT_RANGE,      /* a signal outside the DBC's [min|max] */
    CAN_REJECT_MODE        /* valid, but not in this drive or its present state (the drive's
                            * command functions decide; can_link_parse never returns it) */
} can_reject_t;

/* A short name of a reason ("none", "not ours", "unknown id", "dlc",
 * "range", "mode"), never NULL. */
const char *can_link_reject_name(can_reject_t r);

/* Validates frame f for node and, if it is a valid command, fills *cmd and
 * returns CAN_REJECT_NONE; otherwise *cmd is set to CAN_CMD_NONE and the
 * reason is returned. Pure: the caller decides what a command does (and
 * whether the drive's mode allows it) and counts the refusals. */
can_reject_t can_link_parse(uint8_t node, const can_frame_t *f, can_cmd_t *cmd);

/* Packs a ParamReply of node into *f: op and seq echoed, status
 * (param_status_t, 0-15), the parameter's id and its 32 bits. */
void can_link_pack_param_reply(uint8_t node, uint8_t op, uint8_t status, uint8_t seq, uint16_t id, uint32_t value,
                               can_frame_t *f);

/* The DBC's integer for value x of a signal of factor 1/inv (inv = 1, 100,
 * 500, 1000, 10000 or 100000 in this message set), rounded to nearest and
 * saturated to [lo, hi]; 0 for a non-finite x. Fixed point: the exact
 * 64-bit product of the Q14.17 raw value and inv, rounded (no float).
 * Exposed for the tests. */
int64_t can_link_to_raw(mc_t x, int32_t inv, int64_t lo, int64_t hi);

/* The value of DBC integer r of a signal of factor 1/inv. Fixed point:
 * (r 2^17) / inv rounded, saturated to the Q14.17 range. */
mc_t can_link_from_raw(int64_t r, int32_t inv);

#ifdef __cplusplus
}
#endif

#endif /* COMM_CAN_LINK_H */
