#include "app/bench.h"

#include "io/model/error.h"

namespace dtf::app {
int benchIo(const CommandArgs&) { throw Error("'bench io' is not implemented yet"); }
} // namespace dtf::app
