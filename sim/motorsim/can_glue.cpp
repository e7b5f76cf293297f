#include "motorsim/can_glue.h"

#include <chrono>
#include <stdexcept>
#include <string>

#include "mc_convert.h"

namespace mcsim {

namespace {

const char* command_name(std::uint32_t id)
{
    switch (id & ~0xFu) {
    case 0x200: return "CmdEnable";
    case 0x210: return "CmdMove";
    case 0x220: return "CmdSpeed";
    case 0x230: return "CmdStop";
    case 0x240: return "CmdSetOmegaLim";
    case 0x250: return "CmdClearFaults";
    case 0x260: return "CmdSetRate";
    case 0x280: return "ParamRequest";
    default: return "unknown";
    }
}

// can_apply_fn: the drive's commands, CmdEnable refused while its
// parameters do not design (motorsim/param_glue.h)
can_reject_t apply_command(void* vctx, const can_cmd_t* cmd)
{
    auto* ctx = static_cast<CanDriveContext*>(vctx);
    if (cmd->kind == CAN_CMD_ENABLE && cmd->enable && ctx->params != nullptr && !ctx->params->ready()) {
        return CAN_REJECT_MODE;
    }
    return can_node_apply_drive(&ctx->drive, cmd);
}

}  // namespace

void can_glue_init(CanDriveContext* ctx, unsigned node, std::uint32_t fs_hz)
{
    can_tx_config_t cfg;
    can_tx_defaults(&cfg, static_cast<std::uint8_t>(node > 255u ? 255u : node), static_cast<std::int32_t>(fs_hz));
    if (!can_node_init(&ctx->node, &cfg)) {
        throw std::invalid_argument("--can-node " + std::to_string(node) + ": the node id must be 0-" +
                                    std::to_string(CAN_LINK_NODE_MAX) + " (or the control rate is not > 0)");
    }
}

void can_drive_control_callback(void* vctx, const hal_sample_t* in, hal_command_t* out)
{
    auto* ctx = static_cast<CanDriveContext*>(vctx);
    const auto t0 = std::chrono::steady_clock::now();
    (void)drive_step(&ctx->drive, in, out);
    const double step_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();

    // commands: validated by the node, carried out by the drive between steps
    hal_can_frame_t f;
    for (unsigned k = 0; k < CAN_NODE_RX_PER_STEP && hal_can_receive(&f); ++k) {
        const can_reject_t r = can_node_receive(&ctx->node, in->tick, &f, &apply_command, ctx);
        if (r == CAN_REJECT_NOT_OURS) {
            continue;
        }
        ++ctx->commands;
        if (ctx->log != nullptr) {
            std::fprintf(ctx->log, "motorsim: CAN t = %.4f s: %s (0x%03X, %u bytes) %s%s\n",
                         ctx->t_start_s + static_cast<double>(in->tick) * ctx->ts_s, command_name(f.id),
                         static_cast<unsigned>(f.id), static_cast<unsigned>(f.dlc),
                         r == CAN_REJECT_NONE ? "carried out" : "refused: ",
                         r == CAN_REJECT_NONE ? "" : can_link_reject_name(r));
        }
    }

    // telemetry of this step, then the queue onto the bus
    const mc_t v_bus = in->v_bus_V;
    const mc_t step_time = to_mc(step_us);
    if (ctx->params != nullptr) {
        ctx->node.config_source = ctx->params->config_source();
        ctx->node.params_refused = !ctx->params->ready();
    }
    can_node_step_drive(&ctx->node, &ctx->drive, in->tick, v_bus, step_time);
    while (can_node_peek(&ctx->node, &f)) {
        if (!hal_can_send(&f)) {
            ++ctx->tx_waits;
            break;
        }
        can_node_pop(&ctx->node);
    }
}

}  // namespace mcsim
