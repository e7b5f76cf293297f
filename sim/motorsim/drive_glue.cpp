#include "motorsim/drive_glue.h"

namespace mcsim {

void drive_control_callback(void* ctx, const hal_sample_t* in, hal_command_t* out)
{
    drive_t* d = static_cast<drive_t*>(ctx);
    if (!drive_step(d, in->i_a_A, in->i_b_A, &out->v_a_V, &out->v_b_V)) {
        hal_safe_state();
    }
}

}  // namespace mcsim
