#include "app/commands.h"

#include "io/model/error.h"

namespace dtf::app {
int cmdFit(const CommandArgs&) { throw Error("'fit' is not implemented yet"); }
} // namespace dtf::app
