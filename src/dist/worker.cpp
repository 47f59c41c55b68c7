#include "dist/worker.h"

#include <fmt/format.h>
#include <mpi.h>
#include <sched.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <list>
#include <mutex>
#include <thread>

#include "dist/wire.h"
#include "math/user_text.h"
#include "render/tile_session.h"

namespace anamorph::dist {

namespace {

// Tiles handed to this rank, rendered by its threads; results wait here for the MPI thread.
class TilePool {
 public:
  TilePool(int threads, const std::vector<Aov>& aovs) : aovs_(aovs) {
    for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { work(); });
  }
  ~TilePool() {
    {
      const std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }
  // A new frame: only once every tile of the last one went back (the head hands out a frame's
  // tiles after the previous frame's are all in).
  void set_frame(std::unique_ptr<TileSession> session, int width, int height) {
    const std::lock_guard<std::mutex> lock(mu_);
    session_ = std::move(session);
    width_ = width;
    height_ = height;
    active_.clear();
  }
  // Called by the MPI thread only.
  void add(WorkMessage m) {
    const TileRect& r = m.rect;
    if (!session_) throw std::runtime_error("a tile before its frame");
    if (r.x1 > width_ || r.y1 > height_) throw std::runtime_error("a tile outside the image");
    if (!m.active.empty()) {
      // The tile's part of the frame's mask. Allocated whole at the frame's first pass tile and
      // never resized, so threads reading other tiles' parts meanwhile are safe.
      if (active_.empty()) active_.assign(size_t(width_) * size_t(height_), 0);
      for (int y = r.y0; y < r.y1; ++y)
        std::copy_n(m.active.begin() + ptrdiff_t(y - r.y0) * r.width(), r.width(),
                    active_.begin() + ptrdiff_t(y) * width_ + r.x0);
    }
    {
      const std::lock_guard<std::mutex> lock(mu_);
      queue_.push_back(std::move(m));
      ++in_flight_;
    }
    wake_.notify_one();
  }
  // Results ready to send: (tag, bytes).
  std::vector<std::pair<int, std::vector<char>>> take_results() {
    const std::lock_guard<std::mutex> lock(mu_);
    std::vector<std::pair<int, std::vector<char>>> r;
    r.swap(results_);
    in_flight_ -= r.size();
    return r;
  }
  bool idle() {
    const std::lock_guard<std::mutex> lock(mu_);
    return in_flight_ == 0;
  }
  // Waits until a result is ready or `timeout` passes (the MPI thread's nap: woken at once by a
  // finished tile, so results leave without delay, while messages from the head wait at most
  // the timeout; the tiles queued here cover it).
  void wait_for_result(std::chrono::microseconds timeout) {
    std::unique_lock<std::mutex> lock(mu_);
    done_.wait_for(lock, timeout, [&] { return !results_.empty(); });
  }

 private:
  void work() {
    for (;;) {
      WorkMessage m;
      const TileSession* session = nullptr;
      const std::vector<uint8_t>* active = nullptr;
      {
        std::unique_lock<std::mutex> lock(mu_);
        wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
        if (stop_) return;
        m = std::move(queue_.front());
        queue_.pop_front();
        session = session_.get();
        active = m.active.empty() ? nullptr : &active_;
      }
      std::pair<int, std::vector<char>> result;
      try {
        result = {kResult, render(m, *session, active)};
      } catch (const std::exception& e) {
        const std::string what = e.what();
        result = {kError, std::vector<char>(what.begin(), what.end())};
      }
      {
        const std::lock_guard<std::mutex> lock(mu_);
        results_.push_back(std::move(result));
      }
      done_.notify_one();
    }
  }

  // The tile through TileSession::render, as a local thread renders it. A pass tile's sums so
  // far are unpacked into a buffer first and go back as the pixels the mask leaves on.
  std::vector<char> render(WorkMessage& m, const TileSession& session,
                           const std::vector<uint8_t>* active) const {
    std::unique_ptr<TileBuffer> sums;
    if (!m.whole) {
      sums = std::make_unique<TileBuffer>(m.rect, aovs_);
      unpack_work(m, *sums);
    }
    FarmTile t{m.index, m.rect, width_, m.whole, {m.begin, m.end, m.footprint, active}, sums.get()};
    if (m.resolve) t.plan = &m.plan;
    std::unique_ptr<TileBuffer> buffer;
    const FarmResult r = session.render(t, buffer);
    if (r.resolved) return encode_resolved(*r.resolved, m.rect, r.stats, r.seconds);
    return encode_result(m.index, m.whole ? *r.tile : *sums, m.whole, m.active, r.stats, r.seconds);
  }

  const std::vector<Aov>& aovs_;
  std::mutex mu_;
  std::condition_variable wake_, done_;
  std::deque<WorkMessage> queue_;
  std::vector<std::pair<int, std::vector<char>>> results_;
  size_t in_flight_ = 0;
  bool stop_ = false;
  std::unique_ptr<TileSession> session_;
  int width_ = 0, height_ = 0;
  std::vector<uint8_t> active_;
  std::vector<std::thread> threads_;
};

struct Send {
  std::vector<char> bytes;
  MPI_Request request = MPI_REQUEST_NULL;
};

void send(std::list<Send>& sends, int tag, std::vector<char> bytes) {
  Send& s = sends.emplace_back();
  s.bytes = std::move(bytes);
  MPI_Isend(s.bytes.data(), int(s.bytes.size()), MPI_BYTE, 0, tag, MPI_COMM_WORLD, &s.request);
}

void reap(std::list<Send>& sends) {
  for (auto it = sends.begin(); it != sends.end();) {
    int finished = 0;
    MPI_Test(&it->request, &finished, MPI_STATUS_IGNORE);
    it = finished ? sends.erase(it) : std::next(it);
  }
}

// The CPUs this process may run on: mpirun binds ranks to cores by default (one core each when
// there are two ranks or fewer), which would squeeze a rank's render threads onto one core.
int cpus_allowed() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return int(std::thread::hardware_concurrency());
  return std::max(1, CPU_COUNT(&set));
}

// The number of threads to render with, warning when mpirun bound the rank to fewer CPUs.
int render_threads(int threads, int rank) {
  const int cpus = cpus_allowed();
  if (threads <= 0) return cpus;  // as a process's task arena would
  if (threads > cpus)
    fmt::print(stderr,
               "warning: rank {} renders with {} threads but is bound to {} CPU{}: give mpirun "
               "--bind-to none (or --map-by slot:PE={})\n",
               rank, threads, cpus, cpus == 1 ? "" : "s", threads);
  return threads;
}

// The next message from the head, if one has arrived: its tag and bytes.
bool receive(int& tag, std::vector<char>& bytes) {
  int flag = 0;
  MPI_Status st;
  MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
  if (!flag) return false;
  int count = 0;
  MPI_Get_count(&st, MPI_BYTE, &count);
  bytes.assign(size_t(std::max(count, 0)), 0);
  MPI_Recv(bytes.data(), count, MPI_BYTE, 0, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  tag = st.MPI_TAG;
  return true;
}

// A new frame: its scene loaded, its tiles' shared state built.
void load_frame(const std::vector<char>& bytes, TilePool& pool, const std::vector<Aov>& aovs,
                const std::function<WorkerFrame(double frame)>& load) {
  WireReader r(bytes.data(), bytes.size());
  pool.set_frame(nullptr, 0, 0);  // the last frame's session goes before its scene
  const WorkerFrame f = load(r.get<double>());
  pool.set_frame(f.renderer->session(aovs, f.width, f.height), f.width, f.height);
}

}  // namespace

int serve_tiles(int threads, const std::vector<Aov>& aovs,
                const std::function<WorkerFrame(double frame)>& load) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  threads = render_threads(threads, rank);
  TilePool pool(threads, aovs);
  std::list<Send> sends;
  // Four tiles per thread: one rendering and three waiting, so no thread waits for the head while
  // a request travels (each side looks at MPI every few hundred microseconds when idle).
  const auto room = uint32_t(4 * threads);
  MPI_Send(&room, 1, MPI_UINT32_T, 0, kReady, MPI_COMM_WORLD);
  int code = 0, tag = 0;
  std::vector<char> bytes;
  for (bool stop = false; !stop;) {
    bool busy = false;
    for (auto& [result_tag, r] : pool.take_results()) {
      send(sends, result_tag, std::move(r));
      busy = true;
    }
    reap(sends);
    if (receive(tag, bytes)) {
      busy = true;
      try {
        if (tag == kStop)
          stop = true;
        else if (tag == kFrame)
          load_frame(bytes, pool, aovs, load);
        else if (tag == kWork)
          pool.add(decode_work(bytes.data(), bytes.size()));
      } catch (const std::exception& e) {  // the head ends the job with the message
        fmt::print(stderr, "error: rank {}: {}\n", rank, printable(e.what()));
        const std::string what = e.what();
        send(sends, kError, std::vector<char>(what.begin(), what.end()));
        code = 1;
      }
    }
    if (!busy) pool.wait_for_result(std::chrono::microseconds(500));
  }
  while (!sends.empty()) reap(sends);
  return code;
}

}  // namespace anamorph::dist
