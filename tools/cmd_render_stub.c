#include <stdio.h>
#include "cli.h"
int cli_render(int argc, char **argv) { (void)argc; (void)argv; fputs("lanecast render: not built yet\n", stderr); return CLI_EXIT_FAIL; }
int cli_demo(int argc, char **argv) { (void)argc; (void)argv; fputs("lanecast demo: not built yet\n", stderr); return CLI_EXIT_FAIL; }
