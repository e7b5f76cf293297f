#include "motorsim/drive_glue.h"

namespace mcsim {

void drive_control_callback(void* ctx, const hal_sample_t* in, hal_command_t* out)
{
    paper000_drive_t* d = static_cast<paper000_drive_t*>(ctx);
    if (!paper000_drive_step(d, in, out)) {
        hal_safe_state();
    }
}

}  // namespace mcsim
