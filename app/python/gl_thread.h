// SPDX-License-Identifier: GPL-3.0-or-later
// The one thread that draws. The headless EGL context (render::GlContext::headless()) is current on the
// thread that created it, and Python may call dtfabric.render from any thread: every GL job of the module
// runs here, one at a time, in the order called; the caller waits (without the GIL) for its result or
// exception.
#pragma once

#include <functional>

namespace dtf::python {

// Runs `job` on the GL thread (started on first use, with the headless context made current there) and
// waits for it; rethrows its exception on the calling thread. Throws GlError in a child process forked after
// the thread started.
void runOnGlThread(const std::function<void()>& job);

} // namespace dtf::python
