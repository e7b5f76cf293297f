#include "motorsim/param_glue.h"

#include <cstring>
#include <stdexcept>
#include <vector>

#include "motorsim/flash_file.h"

#if MC_HAS_PARAMS
extern "C" {
#include "config/param_service.h"
}
#endif

namespace mcsim {

#if MC_HAS_PARAMS

struct ParamGlue::Impl {
    Scenario* sc = nullptr;
    const HostDrive* host = nullptr;
    std::vector<std::max_align_t> input;  // the design input (host->input_bytes)
    std::unique_ptr<FlashFile> flash;
    flash_if_t fi{};
    config_store_t store{};
    param_service_t service{};
    uint32_t n_refused = 0;  // stored values the table refused at start
    // the drive, once started
    drive_t drive{};
    drive_config_storage_t* cfg = nullptr;
    std::unique_ptr<drive_config_storage_t> next = std::make_unique<drive_config_storage_t>();
    bool running = false;
    std::string why;  // the last design refusal (err->text points here)

    // param_apply_fn: the design again from the input, the drive
    // initialised from it (left disabled once running)
    static bool apply(void* ctx, const param_table_t* /*t*/, uint16_t id, param_error_t* err)
    {
        auto* g = static_cast<Impl*>(ctx);
        try {
            g->host->design_from_input(*g->sc, g->input.data(), g->next.get());
        } catch (const std::exception& e) {
            g->why = e.what();
            err->status = PARAM_ERR_DESIGN_REFUSED;
            err->id = id;
            err->text = g->why.c_str();
            return false;
        }
        if (!drive_init(&g->drive, g->next.get())) {
            const char* p =
                g->drive.ops->config_problem != nullptr ? g->drive.ops->config_problem(g->next.get()) : nullptr;
            g->why = std::string("the drive refused its configuration") + (p != nullptr ? std::string(": ") + p : "");
            err->status = PARAM_ERR_DESIGN_REFUSED;
            err->id = id;
            err->text = g->why.c_str();
            return false;
        }
        std::memcpy(g->cfg, g->next.get(), sizeof(*g->cfg));
        if (g->running) {
            drive_cmd_t off{};
            off.kind = DRIVE_CMD_ENABLE;
            off.enable = false;
            (void)drive_command(&g->drive, &off);
        }
        return true;
    }
};

ParamGlue::ParamGlue(Scenario& sc, const HostDrive& host, const std::string& flash_path) : impl_(new Impl)
{
    if (host.params == nullptr || host.design_input == nullptr || host.design_from_input == nullptr) {
        throw std::invalid_argument("the " + sc.drive_kind +
                                    " drive has no user parameters (--flash-image, ParamRequest)");
    }
    Impl& g = *impl_;
    g.sc = &sc;
    g.host = &host;
    g.input.assign((host.input_bytes + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t), std::max_align_t{});
    host.design_input(sc, g.input.data());
    config_store_t* store = nullptr;
    const flash_if_t* fi = nullptr;
    if (!flash_path.empty()) {
        g.flash = std::make_unique<FlashFile>(flash_path);
        g.fi = g.flash->interface();
        store = &g.store;
        fi = &g.fi;
    }
    param_error_t err{};
    if (!param_service_init(&g.service, nullptr, nullptr, host.params, g.input.data(), store, fi, &Impl::apply, &g,
                            &err)) {
        throw std::runtime_error(std::string("the ") + sc.drive_kind + " drive's parameters: " + err.text);
    }
}

ParamGlue::~ParamGlue() = default;

drive_t ParamGlue::start(drive_storage_t* storage, drive_config_storage_t* cfg)
{
    Impl& g = *impl_;
    const drive_ops_t* ops = drive_find(g.sc->drive_kind.c_str());
    if (ops == nullptr || !drive_bind(&g.drive, ops, storage)) {
        throw ScenarioError(g.sc->path + ": drive.kind: \"" + g.sc->drive_kind + "\" is not in this build");
    }
    g.cfg = cfg;
    param_error_t err{};
    if (!param_service_start(&g.service, /*keep_targets=*/true, &g.n_refused, &err)) {
        const std::string from = g.flash ? "the parameters of --flash-image " + g.flash->path() : "the parameters";
        const param_desc_t* d = err.id != PARAM_ID_NONE ? params_find(g.host->params, err.id, nullptr) : nullptr;
        throw ScenarioError(from + " do not design" + (d != nullptr ? std::string(" (") + d->name + ")" : "") + ": " +
                            err.text);
    }
    g.running = true;
    return g.drive;
}

std::string ParamGlue::summary() const
{
    const Impl& g = *impl_;
    if (!g.flash) {
        return "the scenario's parameters, no store (save refused)";
    }
    const config_store_t& s = g.store;
    std::string where = "--flash-image " + g.flash->path() + ": ";
    switch (s.source) {
    case CONFIG_SOURCE_RECORD:
        where += "record " + std::to_string(s.seq) + ", " + std::to_string(s.n_kept) + " parameters";
        break;
    case CONFIG_SOURCE_MIGRATED:
        where += "record " + std::to_string(s.seq) + " of another schema: " + std::to_string(s.n_kept) + " kept, " +
                 std::to_string(s.n_defaulted) + " the scenario's";
        break;
    default:
        where +=
            std::string(s.defaults_reason == CONFIG_ERR_NO_RECORD ? "no record (a new image)" : "no valid record") +
            ": the scenario's parameters";
        break;
    }
    if (g.n_refused > 0) {
        where += " (" + std::to_string(g.n_refused) + " stored values refused by the table: the scenario's kept)";
    }
    return where;
}

void ParamGlue::answer(void* ctx, const can_cmd_t* req, can_param_answer_t* ans)
{
    auto* self = static_cast<ParamGlue*>(ctx);
    Impl& g = *self->impl_;
    param_request_t r{};
    r.op = req->param_op;
    r.seq = req->param_seq;
    r.id = req->param_id;
    r.value.u32 = req->param_value;
    drive_status_t st{};
    drive_status(&g.drive, &st);
    param_reply_t out{};
    param_service_request(&g.service, &r, st.enabled, &out);
    ans->status = static_cast<uint8_t>(out.status);
    ans->id = out.id;
    ans->value = out.value.u32;
}

bool ParamGlue::ready() const { return param_service_ready(&impl_->service); }
std::uint8_t ParamGlue::config_source() const { return param_service_config_source(&impl_->service); }

#else  // the build has no parameters (fixed point)

struct ParamGlue::Impl {};

// cppcheck-suppress constParameter ; the float build's signature, whose constructor keeps sc to design from
ParamGlue::ParamGlue(Scenario& sc, const HostDrive& /*host*/, const std::string& /*flash_path*/)
{
    throw std::invalid_argument("the " + sc.drive_kind +
                                " drive's parameters are served by the float build only (this one is fixed point)");
}
ParamGlue::~ParamGlue() = default;
drive_t ParamGlue::start(drive_storage_t* /*storage*/, drive_config_storage_t* /*cfg*/) { return drive_t{}; }
std::string ParamGlue::summary() const { return std::string(); }
void ParamGlue::answer(void* /*ctx*/, const can_cmd_t* /*req*/, can_param_answer_t* ans) { ans->status = 1; }
bool ParamGlue::ready() const { return false; }
std::uint8_t ParamGlue::config_source() const { return 0; }

#endif

}  // namespace mcsim
