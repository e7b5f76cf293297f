#include "control/twisting.h"

#include <stdbool.h>

void twisting_init(twisting_t *tw, const twisting_config_t *cfg) { tw->cfg = *cfg; }
