#include "app/commands.h"

#include "io/model/error.h"

namespace dtf::app {
int cmdRender(const CommandArgs&) { throw Error("'render' is not implemented yet"); }
} // namespace dtf::app
