#include "app/commands.h"

#include "io/model/error.h"

namespace dtf::app {
int cmdInfo(const CommandArgs&) { throw Error("'info' is not implemented yet"); }
} // namespace dtf::app
