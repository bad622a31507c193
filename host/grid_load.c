/* placeholder, replaced below */
#include "grid.h"
