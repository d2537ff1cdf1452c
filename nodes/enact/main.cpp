// enact: the command line of the enact haptics framework (its commands: command_table.cpp)
#include "nodes/enact/command_table.h"

int main(int argc, char** argv) { return enact::cli::run_command(argc, argv); }
