/* main.c — strata's entry point; everything else is in the library. */
#include "cli.h"

int main(int argc, char **argv) { return st_cli_main(argc, argv); }
