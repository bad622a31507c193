// The public header alone must compile as C++11 (extern "C", no C-only syntax).
#include "lanecast/lanecast.h"

int main() { return LC_OK; }
