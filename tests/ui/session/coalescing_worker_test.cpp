// SPDX-License-Identifier: GPL-3.0-or-later
// The one coalescing worker under the session's surface and tract work: latest request wins, a newer
// request cancels the running job of a cancelling lane, queue lanes keep every request, superseded lanes
// are dropped, lower lanes run first, progress is seen from the caller's thread, and the destructor cancels
// and joins. Jobs are held at a gate the test opens (no sleeps decide an outcome), so the runs are
// deterministic and ThreadSanitizer sees every hand-over through the worker's mutex or a future.
#include "ui/session/coalescing_worker.h"

#include <atomic>
#include <chrono>
#include <future>
#include <gtest/gtest.h>
#include <memory>
#include <thread>
#include <vector>

using dtf::session::CoalescingWorker;
using dtf::session::WorkContext;
using dtf::session::WorkLane;

namespace {

// A job that waits for its gate (when it has one) and reports its value; `cancellable` jobs return early
// when cancelled and report nothing.
struct Job {
  int value = 0;
  std::shared_ptr<std::promise<void>> started; // set when the job starts
  std::shared_future<void> gate;               // waited for before finishing
  bool cancellable = false;
};

struct Result {
  int value = 0;
  bool sawCancel = false;
};

std::optional<Result> perform(Job& job, WorkContext& context) {
  context.setStage("job " + std::to_string(job.value));
  context.setCount(1, 4);
  if (job.started) job.started->set_value();
  if (job.gate.valid()) {
    // A cancellable job polls its flag the way long loops do; others wait for the gate only.
    while (job.gate.wait_for(std::chrono::milliseconds(1)) != std::future_status::ready)
      if (job.cancellable && context.cancelled()) return std::nullopt;
  }
  return Result{job.value, context.cancelled()};
}

// Waits until the worker is idle and returns every result's value in order.
template <class W> std::vector<Result> results(W& w) {
  std::vector<Result> out;
  while (true) {
    Result r;
    if (w.poll(r)) {
      out.push_back(r);
      continue;
    }
    if (!w.busy()) break;
    std::this_thread::yield();
  }
  return out;
}

// A job that blocks the worker until the returned promise is set.
Job blocker(int value, std::shared_ptr<std::promise<void>>& started, std::promise<void>& open) {
  started = std::make_shared<std::promise<void>>();
  return Job{value, started, open.get_future().share(), false};
}

} // namespace

TEST(CoalescingWorker, LatestRequestWinsWhileTheWorkerIsBusy) {
  CoalescingWorker<Job, Result> w(perform);
  std::promise<void> open;
  std::shared_ptr<std::promise<void>> started;
  w.request(blocker(1, started, open));
  started->get_future().wait(); // job 1 runs; the next requests wait
  for (int v = 2; v <= 5; ++v)
    w.request(Job{v});
  EXPECT_TRUE(w.pending(0));
  open.set_value();
  const auto r = results(w);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].value, 1);
  EXPECT_EQ(r[1].value, 5); // 2, 3 and 4 were replaced before they started
  EXPECT_FALSE(w.pending(0));
}

TEST(CoalescingWorker, ANewerRequestCancelsTheRunningJobOfACancellingLane) {
  CoalescingWorker<Job, Result> w(perform, {WorkLane{true, true}});
  std::promise<void> never; // the first job only ends by its cancel flag
  auto started = std::make_shared<std::promise<void>>();
  w.request(Job{1, started, never.get_future().share(), true});
  started->get_future().wait();
  w.request(Job{2});
  const auto r = results(w);
  ASSERT_EQ(r.size(), 1u); // the cancelled job reported nothing
  EXPECT_EQ(r[0].value, 2);
  EXPECT_FALSE(r[0].sawCancel); // the new job starts with a clear flag
  never.set_value();
}

TEST(CoalescingWorker, QueueLanesKeepEveryRequestAndLowerLanesRunFirst) {
  // Lane 0 coalesces, lane 1 queues (saves).
  CoalescingWorker<Job, Result> w(perform, {WorkLane{}, WorkLane{false, false}});
  std::promise<void> open;
  std::shared_ptr<std::promise<void>> started;
  w.request(blocker(0, started, open), 1);
  started->get_future().wait();
  w.request(Job{10}, 1);
  w.request(Job{11}, 1);
  w.request(Job{1}, 0);
  w.request(Job{2}, 0);
  open.set_value();
  const auto r = results(w);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r[0].value, 0);
  EXPECT_EQ(r[1].value, 2); // lane 0 first, its latest request only
  EXPECT_EQ(r[2].value, 10);
  EXPECT_EQ(r[3].value, 11);
}

TEST(CoalescingWorker, ARequestDropsTheJobsWaitingInTheLanesItSupersedes) {
  // As a load supersedes the surface requests of the data it replaces.
  CoalescingWorker<Job, Result> w(perform, {WorkLane{}, WorkLane{}});
  std::promise<void> open;
  std::shared_ptr<std::promise<void>> started;
  w.request(blocker(0, started, open), 1);
  started->get_future().wait();
  w.request(Job{5}, 1);
  w.request(Job{7}, 0, {1});
  open.set_value();
  const auto r = results(w);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[1].value, 7); // job 5 never ran
}

TEST(CoalescingWorker, CancelReachesTheRunningJobAndTheOnesWaiting) {
  CoalescingWorker<Job, Result> w(perform);
  std::promise<void> open;
  std::shared_ptr<std::promise<void>> started;
  w.request(blocker(1, started, open));
  started->get_future().wait();
  w.request(Job{2});
  w.cancel(0);
  open.set_value();
  const auto r = results(w);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_TRUE(r[0].sawCancel);
  EXPECT_EQ(r[1].value, 2);
  EXPECT_TRUE(r[1].sawCancel); // it still ran and reported, so a caller waiting for it hears of it
  w.request(Job{3});
  const auto after = results(w);
  ASSERT_EQ(after.size(), 1u);
  EXPECT_FALSE(after[0].sawCancel); // a later request is not cancelled
}

TEST(CoalescingWorker, ProgressOfTheRunningJobIsSeenFromTheCallersThread) {
  CoalescingWorker<Job, Result> w(perform, {WorkLane{}, WorkLane{}});
  std::string stage;
  EXPECT_FALSE(w.progress(0, &stage));
  std::promise<void> open;
  std::shared_ptr<std::promise<void>> started;
  w.request(blocker(4, started, open), 1);
  started->get_future().wait();
  std::size_t done = 0, planned = 0;
  EXPECT_FALSE(w.progress(0, &stage)); // another lane's job
  ASSERT_TRUE(w.progress(1, &stage, &done, &planned));
  EXPECT_EQ(stage, "job 4");
  EXPECT_EQ(done, 1u);
  EXPECT_EQ(planned, 4u);
  EXPECT_TRUE(w.running(1));
  open.set_value();
  results(w);
  EXPECT_FALSE(w.running(1));
}

TEST(CoalescingWorker, DestructionCancelsTheRunningJobDropsTheWaitingOnesAndJoins) {
  std::promise<void> never;
  std::atomic<int> ran{0};
  {
    CoalescingWorker<Job, Result> w(
        [&](Job& job, WorkContext& context) {
          ++ran;
          return perform(job, context);
        },
        {WorkLane{}, WorkLane{false, false}});
    auto started = std::make_shared<std::promise<void>>();
    w.request(Job{1, started, never.get_future().share(), true});
    started->get_future().wait();
    w.request(Job{2}, 1);
    w.request(Job{3}, 1);
  } // joins: the running job sees its cancel flag; 2 and 3 never start
  EXPECT_EQ(ran.load(), 1);
  never.set_value();
}
