/* SPDX-License-Identifier: MIT */
/* EXPLORE_OFF: stand still; the map still updates. */
#include "modes.h"

EXPLORE_STANDING_MODE(off)
