#include "app/commands.h"

#include "io/model/error.h"

namespace dtf::app {
int cmdPhantom(const CommandArgs&) { throw Error("'phantom' is not implemented yet"); }
} // namespace dtf::app
