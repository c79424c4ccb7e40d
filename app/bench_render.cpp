#include "app/bench.h"

#include "io/model/error.h"

namespace dtf::app {
int benchRender(const CommandArgs&) { throw Error("'bench render' is not implemented yet"); }
} // namespace dtf::app
