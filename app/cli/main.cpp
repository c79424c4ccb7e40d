#include "app/cli/commands.h"

int main(int argc, char** argv) { return dtf::app::runCli(argc, argv); }
