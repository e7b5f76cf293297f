#include "motorsim/drive_glue.h"

namespace mcsim {

void drive_control_callback(void* ctx, const hal_sample_t* in, hal_command_t* out)
{
    if (!drive_step(static_cast<drive_t*>(ctx), in, out)) {
        hal_safe_state();
    }
}

}  // namespace mcsim
