// SPDX-License-Identifier: GPL-3.0-or-later
// One background thread that performs a front end's requests off its UI thread, latest request first. Jobs
// wait in lanes: in a coalescing lane a request replaces the job waiting there (dragging a slider costs one
// job per result the user can see) and may cancel the running job of its lane (it is out of date); in a
// queue lane every request runs (saves). A request may also drop the jobs waiting in lanes it supersedes (a
// new load makes waiting surface requests of the old data pointless). Waiting jobs run lowest lane first.
// The job reports progress (a stage text, a count done of a count planned) and sees its cancel flag through
// WorkContext; results are polled by the UI thread. The destructor cancels the running job, drops the waiting
// ones and joins. Every shared member is guarded by one mutex (the cancel flag is atomic for the job's
// loops).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <initializer_list>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace dtf::session {

// What a running job sees: its cancel flag and where it reports progress. Used on the worker thread only;
// the worker reads the progress under its mutex.
class WorkContext {
public:
  // Set when the job is out of date (a newer request in a cancelling lane), cancelled, or the worker stops.
  const std::atomic<bool>& cancelFlag() const { return cancel_; }
  bool cancelled() const { return cancel_.load(std::memory_order_relaxed); }
  void setStage(const std::string& stage) {
    std::lock_guard lock(*mutex_);
    stage_ = stage;
  }
  void setCount(std::size_t done, std::size_t planned) {
    std::lock_guard lock(*mutex_);
    done_ = done;
    planned_ = planned;
  }

private:
  template <class, class> friend class CoalescingWorker;
  explicit WorkContext(std::mutex* mutex) : mutex_(mutex) {}
  std::mutex* mutex_;
  std::atomic<bool> cancel_{false};
  std::string stage_; // guarded by *mutex_
  std::size_t done_ = 0, planned_ = 0;
};

struct WorkLane {
  bool coalesce = true;        // a request replaces the job waiting in the lane; false: every request queues
  bool cancelsRunning = false; // a request cancels the running job of this lane
};

template <class Job, class Result> class CoalescingWorker {
public:
  // Performs a job on the worker thread; nullopt reports nothing (e.g. a job cancelled as out of date).
  // Exceptions escaping it are the caller's to catch inside `run` (the thread would terminate).
  using Run = std::function<std::optional<Result>(Job&, WorkContext&)>;

  explicit CoalescingWorker(Run run, std::vector<WorkLane> lanes = {WorkLane{}})
      : run_(std::move(run)), rules_(std::move(lanes)), waiting_(rules_.size()),
        cancelWaiting_(rules_.size()), thread_([this] { loop(); }) {}

  ~CoalescingWorker() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
      for (auto& lane : waiting_)
        lane.clear();
      context_.cancel_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  CoalescingWorker(const CoalescingWorker&) = delete;
  CoalescingWorker& operator=(const CoalescingWorker&) = delete;

  // Queues `job` in `lane` by the lane's rule, after dropping the jobs waiting in the lanes `supersedes`.
  void request(Job job, std::size_t lane = 0, std::initializer_list<std::size_t> supersedes = {}) {
    {
      std::lock_guard lock(mutex_);
      for (std::size_t l : supersedes) {
        waiting_.at(l).clear();
        cancelWaiting_[l] = false;
      }
      auto& q = waiting_.at(lane);
      if (rules_[lane].coalesce) {
        q.clear();
        cancelWaiting_[lane] = false;
      }
      q.push_back(std::move(job));
      if (rules_[lane].cancelsRunning && runningLane_ == static_cast<int>(lane)) context_.cancel_ = true;
    }
    wake_.notify_all();
  }

  // Cancels the running job of `lane`, and the ones waiting there start cancelled (they still run and report,
  // so a front end waiting for their result hears of them).
  void cancel(std::size_t lane) {
    std::lock_guard lock(mutex_);
    if (runningLane_ == static_cast<int>(lane)) context_.cancel_ = true;
    if (!waiting_.at(lane).empty()) cancelWaiting_[lane] = true;
  }

  // Takes the oldest result, if any.
  bool poll(Result& out) {
    std::lock_guard lock(mutex_);
    if (results_.empty()) return false;
    out = std::move(results_.front());
    results_.pop_front();
    return true;
  }

  // A job waits or runs, or a result waits to be polled.
  bool busy() const {
    std::lock_guard lock(mutex_);
    if (runningLane_ >= 0 || !results_.empty()) return true;
    for (const auto& lane : waiting_)
      if (!lane.empty()) return true;
    return false;
  }
  // A job of `lane` waits or runs.
  bool pending(std::size_t lane) const {
    std::lock_guard lock(mutex_);
    return runningLane_ == static_cast<int>(lane) || !waiting_.at(lane).empty();
  }
  // A job of `lane` runs.
  bool running(std::size_t lane) const {
    std::lock_guard lock(mutex_);
    return runningLane_ == static_cast<int>(lane);
  }
  // The running job's progress when it belongs to `lane`: `stage` is assigned only when it differs (no
  // allocation per frame), done/planned as reported. False when no job of `lane` runs.
  bool progress(std::size_t lane, std::string* stage, std::size_t* done = nullptr,
                std::size_t* planned = nullptr) const {
    std::lock_guard lock(mutex_);
    if (runningLane_ != static_cast<int>(lane)) return false;
    if (stage && *stage != context_.stage_) *stage = context_.stage_;
    if (done) *done = context_.done_;
    if (planned) *planned = context_.planned_;
    return true;
  }

private:
  void loop() {
    while (true) {
      std::optional<Job> job;
      std::size_t lane = 0;
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || anyWaiting(); });
        if (stop_) return;
        while (waiting_[lane].empty())
          ++lane;
        job.emplace(std::move(waiting_[lane].front()));
        waiting_[lane].pop_front();
        context_.cancel_ = cancelWaiting_[lane];
        if (waiting_[lane].empty()) cancelWaiting_[lane] = false;
        context_.stage_.clear();
        context_.done_ = context_.planned_ = 0;
        runningLane_ = static_cast<int>(lane);
      }
      std::optional<Result> r = run_(*job, context_);
      job.reset(); // release what the job holds before the front end hears of its end
      std::lock_guard lock(mutex_);
      if (r) results_.push_back(std::move(*r));
      runningLane_ = -1;
    }
  }
  bool anyWaiting() const {
    for (const auto& lane : waiting_)
      if (!lane.empty()) return true;
    return false;
  }

  Run run_;
  std::vector<WorkLane> rules_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<std::deque<Job>> waiting_;
  std::vector<char> cancelWaiting_;
  std::deque<Result> results_;
  int runningLane_ = -1;
  bool stop_ = false;
  WorkContext context_{&mutex_};
  std::thread thread_; // last: starts once everything above exists
};

} // namespace dtf::session
