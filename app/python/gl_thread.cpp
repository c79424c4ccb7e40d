// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/python/gl_thread.h"

#include "io/model/error.h"

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <unistd.h>

namespace dtf::python {

namespace {

struct Job {
  const std::function<void()>* work = nullptr;
  std::exception_ptr error;
  bool done = false;
};

struct GlThread {
  std::mutex mutex;
  std::condition_variable wake, finished;
  std::deque<Job*> queue;
  const pid_t pid = ::getpid(); // the process whose thread holds the context

  GlThread() {
    // Detached and never joined: the context lives for the process, as in the command-line tool; at exit
    // the thread waits on the condition variable and the process ends under it.
    std::thread([this] { loop(); }).detach();
  }

  void loop() {
    for (;;) {
      Job* job = nullptr;
      {
        std::unique_lock lock(mutex);
        wake.wait(lock, [this] { return !queue.empty(); });
        job = queue.front();
        queue.pop_front();
      }
      try {
        (*job->work)();
      } catch (...) {
        job->error = std::current_exception();
      }
      {
        std::lock_guard lock(mutex);
        job->done = true;
      }
      finished.notify_all();
    }
  }
};

GlThread& glThread() {
  static GlThread* thread = new GlThread(); // never destroyed (see above)
  return *thread;
}

} // namespace

void runOnGlThread(const std::function<void()>& work) {
  GlThread& t = glThread();
  // A child forked after the first render has neither the thread nor a usable context.
  if (::getpid() != t.pid)
    throw GlError(
        "dtfabric cannot render in a process forked after it rendered (the GL context belongs to the "
        "parent): use multiprocessing's 'spawn' or 'forkserver' start method");
  Job job;
  job.work = &work;
  {
    std::lock_guard lock(t.mutex);
    t.queue.push_back(&job);
  }
  t.wake.notify_one();
  std::unique_lock lock(t.mutex);
  t.finished.wait(lock, [&] { return job.done; });
  if (job.error) std::rethrow_exception(job.error);
}

} // namespace dtf::python
