/* control_none.c: no controller in C (a run without one, or one that stays in Python). */
#include "legdsl_control.h"

const int64_t leg_has_c_controller = 0;
const leg_controller leg_the_controller = {0};
