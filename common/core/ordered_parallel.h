// An ordered parallel loop on std::thread: independent work items computed in parallel, their
// results used strictly in order. This is how 3DVO codes GOMs in parallel and still writes one
// stream that is byte-identical for any number of threads.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace tdvo {

// Runs work(i) for i = 0 .. count - 1 on `threads` worker threads and hands each result to
// consume(i, result) on the calling thread, in increasing i, as soon as result i is ready.
// At most `window` (>= 1) items are started but not yet consumed, which bounds the memory held
// by results waiting for their turn. work must be safe to call from several threads at once
// (for different i); consume runs on the calling thread only.
//
// Errors come out as a sequential loop would give them: an exception thrown by work(i) is
// rethrown on the calling thread when item i's turn comes (items before it are consumed
// first); an exception thrown by consume ends the loop. Either way, items already running are
// finished, no new ones are started, and every thread is joined before the exception leaves.
//
// threads <= 1 (or a single item): no thread is started; work(i) then consume(i, result), in
// order, on the calling thread.
template <class Result, class Work, class Consume>
void orderedParallelFor(size_t count, int threads, size_t window, Work work, Consume consume) {
  if (threads <= 1 || count <= 1) {
    for (size_t i = 0; i < count; ++i) {
      Result result = work(i);
      consume(i, result);
    }
    return;
  }
  if (window < 1) window = 1;

  struct Slot {
    std::optional<Result> result;
    std::exception_ptr error;
    bool done = false;
  };
  std::vector<Slot> slots(window);  // item i lives in slots[i % window] until consumed
  std::mutex mutex;
  std::condition_variable canStart, isDone;
  size_t next = 0;      // next item to start
  size_t consumed = 0;  // items consumed so far
  bool stop = false;

  auto worker = [&]() {
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      canStart.wait(lock, [&] { return stop || next >= count || next < consumed + window; });
      if (stop || next >= count) return;
      const size_t i = next++;
      lock.unlock();
      Slot slot;
      try {
        slot.result.emplace(work(i));
      } catch (...) {
        slot.error = std::current_exception();
      }
      lock.lock();
      slot.done = true;
      slots[i % window] = std::move(slot);
      isDone.notify_all();
    }
  };

  // Joins the workers however the loop ends (normally or by an exception).
  struct Pool {
    std::vector<std::thread> threads;
    std::mutex& mutex;
    std::condition_variable& canStart;
    bool& stop;
    ~Pool() {
      {
        std::lock_guard<std::mutex> lock(mutex);
        stop = true;
      }
      canStart.notify_all();
      for (std::thread& t : threads)
        t.join();
    }
  } pool{{}, mutex, canStart, stop};
  const size_t workers = std::min(static_cast<size_t>(threads), count);
  for (size_t t = 0; t < workers; ++t)
    pool.threads.emplace_back(worker);

  for (size_t i = 0; i < count; ++i) {
    Slot slot;
    {
      std::unique_lock<std::mutex> lock(mutex);
      isDone.wait(lock, [&] { return slots[i % window].done; });
      slot = std::move(slots[i % window]);
      slots[i % window] = Slot();
      consumed = i + 1;
    }
    canStart.notify_all();
    if (slot.error) std::rethrow_exception(slot.error);
    consume(i, *slot.result);
  }
}

}  // namespace tdvo
