// param_glue.h - motorsim's drive with its user parameters, as a board runs
// it (firmware/config/param_service.h): the scenario's design input is the
// base, the store kept in --flash-image (motorsim/flash_file.h) goes over
// it at start, the drive's host part designs the configuration from the
// result (HostDrive.design_from_input), and on CAN the drive's node
// answers ParamRequest with it: read, write (a drive's parameter while
// disabled: the design runs again and the drive is initialised from it,
// left disabled), save (into the image), defaults (the scenario's), list.
// A write the design refuses keeps the value and the drive disabled
// (CmdEnable refused) until a later change designs. Only in builds with
// the parameters (float); elsewhere the constructor refuses naming the
// build.
#ifndef MCSIM_MOTORSIM_PARAM_GLUE_H
#define MCSIM_MOTORSIM_PARAM_GLUE_H

#include <cstdint>
#include <memory>
#include <string>

#include "host_drives/host_drive.h"

extern "C" {
#include "comm/can_node.h"
}

namespace mcsim {

class ParamGlue {
public:
    // The drive's parameters over the scenario's design input; flash_path
    // empty: no store (save refused: store_failed). Throws
    // std::invalid_argument when the drive or the build has no parameters,
    // std::runtime_error naming the image when it cannot be read.
    ParamGlue(Scenario& sc, const HostDrive& host, const std::string& flash_path);
    ~ParamGlue();
    ParamGlue(const ParamGlue&) = delete;
    ParamGlue& operator=(const ParamGlue&) = delete;

    // The drive bound to storage, designed from the parameters into *cfg
    // and initialised: the start. Throws ScenarioError naming the image
    // and the design's reason when the stored parameters do not design.
    drive_t start(drive_storage_t* storage, drive_config_storage_t* cfg);

    // One line on where the parameters came from (the image's record, a
    // migration, none), for the log.
    std::string summary() const;

    // The CAN node's ParamRequest handler (can_param_fn; ctx: this).
    static void answer(void* ctx, const can_cmd_t* req, can_param_answer_t* ans);
    // True while the parameters design (else CmdEnable is refused).
    bool ready() const;
    // Where the parameters came from at start, the heartbeat's ConfigSource
    // (param_service_config_source).
    std::uint8_t config_source() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_PARAM_GLUE_H
