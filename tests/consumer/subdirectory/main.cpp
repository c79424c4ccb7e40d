// SPDX-License-Identifier: GPL-3.0-or-later
// Compiled only when the host is built: the umbrella header through dtfabric::dtfabric's build-tree
// include directories.
#include <dtfabric/dtfabric.h>

int main() { return dtf::render::Camera().orthographic ? 0 : 1; }
