#include "app_drive.h"

#include <string.h>

#include "stm32_backend.h"
#include "stm32f405_regs.h"

#if !defined(MC_DRIVE_NAME) || !defined(MC_DRIVE_OPS)
#error "MC_DRIVE_NAME, MC_DRIVE_OPS: the image's drive and its operations, defined by CMakeLists.txt from MC_DRIVE"
#endif

/* The drive's operations, bound directly rather than looked up with
 * drive_find: the registry's table would keep every drive in the image
 * (--gc-sections drops the others this way); MC_DRIVE was checked against
 * the registry at configure time (cmake/mc_drive.cmake). */
extern const drive_ops_t MC_DRIVE_OPS;

const char *app_drive_name(void) { return MC_DRIVE_NAME; }

bool app_drive_init(app_drive_t *a, const uint32_t *cfg_words, uint32_t cfg_bytes, uint32_t control_hz, uint8_t node,
                    bool can)
{
    const drive_ops_t *ops = &MC_DRIVE_OPS;
    if (!drive_bind(&a->drive, ops, &a->storage)) {
        return false;
    }
    /* the words were designed on the host for this drive's config type
     * (firmware/drives/<drive>/boards/, the PIL vectors) */
    drive_config_storage_t cfg;
    if (cfg_bytes != ops->config_bytes || cfg_bytes > (uint32_t)sizeof cfg) {
        return false;
    }
    memcpy(&cfg, cfg_words, cfg_bytes);
    can_tx_config_t tc;
    can_tx_defaults(&tc, node, (int32_t)control_hz);
    if (!can_node_init(&a->node, &tc)) {
        return false; /* a node id the DBC has no room for */
    }
    a->can = can;
    a->step_cycles = 0u;
    a->step_dir = false;
    a->params = NULL;
    return drive_init(&a->drive, &cfg);
}

bool app_drive_init_params(app_drive_t *a, app_params_t *p, const drive_design_ops_t *design,
                           const param_table_t *board_table, const app_param_value_t *values, uint32_t n_values,
                           uint32_t control_hz, bool can, const flash_if_t *flash, const app_params_hooks_t *hooks,
                           param_error_t *err)
{
    a->can = can;
    a->step_cycles = 0u;
    a->step_dir = false;
    a->params = NULL;
    if (!drive_bind(&a->drive, &MC_DRIVE_OPS, &a->storage)) {
        err->status = PARAM_ERR_BAD_REQUEST;
        err->id = PARAM_ID_NONE;
        err->text = "the drive's state does not fit drive_storage_t";
        return false;
    }
    if (!app_params_init(p, design, board_table, &a->drive, &a->node, flash, hooks, err) ||
        !app_params_start(p, values, n_values, control_hz, err)) {
        return false;
    }
    a->params = p;
    a->node.config_source = param_service_config_source(&p->service); /* fixed at the start */
    return true;
}

/* can_apply_fn over the app: CmdEnable waits for the parameters to design
 * and for nothing to be in flight (app_params_may_enable); the rest is
 * the drive's. */
static can_reject_t apply_command(void *ctx, const can_cmd_t *cmd)
{
    app_drive_t *a = (app_drive_t *)ctx;
    if (cmd->kind == CAN_CMD_ENABLE && cmd->enable && a->params != NULL && !app_params_may_enable(a->params)) {
        return CAN_REJECT_MODE;
    }
    return can_node_apply_drive(&a->drive, cmd);
}

bool app_drive_step_dir(app_drive_t *a, const step_shaper_config_t *cfg, int32_t count0)
{
    a->step_dir = a->drive.ops->kind == DRIVE_KIND_POSITION && step_shaper_init(&a->shaper, cfg, count0);
    return a->step_dir;
}

/* the step/dir input's sample: the shaper's move, if any, offered to the drive */
static void step_dir_sample(app_drive_t *a)
{
    int32_t count = 0;
    if (!stm32_backend_step_count(&count)) {
        return;
    }
    /* where the reference rests: only when a move may be offered (the
     * drive's status costs more than the check) */
    mc_t rest = MC_ZERO;
    if (count != a->shaper.count_moved) {
        drive_status_t st;
        drive_status(&a->drive, &st);
        rest = st.theta_ref_rad;
    }
    step_shaper_move_t m;
    step_shaper_step(&a->shaper, count, rest, &m);
    if (m.move) {
        drive_cmd_t c = {0};
        c.kind = DRIVE_CMD_MOVE;
        c.theta_to_rad = m.theta_to_rad;
        c.duration_s = m.duration_s;
        step_shaper_answer(&a->shaper, drive_command(&a->drive, &c) == DRIVE_REFUSE_NONE);
    }
    a->node.excess_steps = a->shaper.excess_steps;
}

void app_drive_control(void *ctx, const hal_sample_t *in, hal_command_t *out)
{
    app_drive_t *a = (app_drive_t *)ctx;
    const uint32_t t0 = SYST_CVR;
    const bool ok = drive_step(&a->drive, in, out);
    const uint32_t t1 = SYST_CVR;
    a->step_cycles = (t0 - t1) & 0x00FFFFFFu; /* SysTick counts down */
    if (!ok && !a->can) {
        hal_safe_state();
        return;
    }
    if (a->step_dir) {
        step_dir_sample(a);
    }
    if (!a->can) {
        return;
    }
    /* on CAN a latched fault keeps the node alive (0 V from the drive):
     * the heartbeat reports it and CmdClearFaults can clear it */
    hal_can_frame_t f;
    for (uint32_t k = 0; k < CAN_NODE_RX_PER_STEP && hal_can_receive(&f); ++k) {
        (void)can_node_receive(&a->node, in->tick, &f, &apply_command, a);
    }
    if (a->params != NULL) {
        app_params_control(a->params, in->tick);
        a->node.params_refused = !param_service_ready(&a->params->service);
    }
    can_node_step_drive(&a->node, &a->drive, in->tick, in->v_bus_V, MC_ZERO);
    while (can_node_peek(&a->node, &f) && hal_can_send(&f)) {
        can_node_pop(&a->node);
    }
}
