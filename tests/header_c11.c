/* The public header alone must compile as strict ISO C11 (-pedantic -Werror). */
#include "lanecast/lanecast.h"

int main(void) { return LC_OK; }
