#include "dist/head.h"

#include <fmt/format.h>
#include <mpi.h>

#include <chrono>
#include <stdexcept>
#include <thread>

#include "dist/wire.h"
#include "dist/world.h"

namespace anamorph::dist {

namespace {

// Nothing arrived: a short nap instead of spinning (Open MPI's blocking calls spin and would take
// a core from the render threads of a worker on the same machine).
void nap() { std::this_thread::sleep_for(std::chrono::microseconds(250)); }

}  // namespace

struct HeadFarm::Send {
  std::vector<char> bytes;
  MPI_Request request = MPI_REQUEST_NULL;
};

HeadFarm::HeadFarm(std::vector<Aov> aovs, const std::atomic<bool>* cancel)
    : aovs_(std::move(aovs)), cancel_(cancel) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  room_.assign(size_t(size - 1), 0);
  for (int i = 1; i < size; ++i) {
    uint32_t room = 0;
    MPI_Recv(&room, 1, MPI_UINT32_T, i, kReady, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    room_[size_t(i - 1)] = int(room);
  }
}

HeadFarm::~HeadFarm() {
  if (cancel_ && cancel_->load()) return;  // World aborts the job: a worker may be gone
  if (!out_.empty()) {
    // An error ended the render with tiles out (a worker's error, or the head's): their results
    // would never be received, and a worker waiting to send one would never stop. Abort the job.
    World::abort_on_exit(1);
    return;
  }
  for (int i = 1; i <= workers(); ++i) send(i, kStop, {});
  while (sends_pending()) nap();
}

void HeadFarm::send(int rank, int tag, std::vector<char> bytes) {
  Send& s = sends_.emplace_back();
  s.bytes = std::move(bytes);
  // Never a blocking send: a worker may be sending a large tile back at the same moment, and two
  // blocking sends of large messages wait for each other forever.
  MPI_Isend(s.bytes.data(), int(s.bytes.size()), MPI_BYTE, rank, tag, MPI_COMM_WORLD, &s.request);
}

bool HeadFarm::sends_pending() {
  for (auto it = sends_.begin(); it != sends_.end();) {
    int finished = 0;
    MPI_Test(&it->request, &finished, MPI_STATUS_IGNORE);
    it = finished ? sends_.erase(it) : std::next(it);
  }
  return !sends_.empty();
}

void HeadFarm::begin_frame(double frame) {
  WireWriter w;
  w.put(frame);
  for (int i = 1; i <= workers(); ++i) send(i, kFrame, w.bytes());
}

bool HeadFarm::receive(const std::function<void(FarmResult&)>& done, size_t& out) {
  int flag = 0;
  MPI_Status st;
  MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
  if (!flag) return false;
  int count = 0;
  MPI_Get_count(&st, MPI_BYTE, &count);
  std::vector<char> bytes(size_t(std::max(count, 0)));
  MPI_Recv(bytes.data(), count, MPI_BYTE, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  if (st.MPI_TAG == kError)
    throw std::runtime_error(
        fmt::format("rank {}: {}", st.MPI_SOURCE, std::string(bytes.begin(), bytes.end())));
  if (st.MPI_TAG != kResult)
    throw std::runtime_error(fmt::format("rank {} sent message {}", st.MPI_SOURCE, st.MPI_TAG));
  const auto sent = out_.find(result_index(bytes.data(), bytes.size()));
  if (sent == out_.end())
    throw std::runtime_error(fmt::format("rank {} sent a tile it was not given", st.MPI_SOURCE));
  FarmResult r =
      decode_result(bytes.data(), bytes.size(), aovs_, sent->second.first, sent->second.second);
  out_.erase(sent);
  r.rank = st.MPI_SOURCE;
  ++room_[size_t(st.MPI_SOURCE - 1)];
  --out;
  done(r);
  return true;
}

void HeadFarm::run(const std::function<std::optional<FarmTile>()>& next,
                   const std::function<void(FarmResult&)>& done) {
  size_t out = 0;  // tiles handed out and not back yet
  bool more = true;
  while (more || out > 0) {
    if (cancel_ && cancel_->load()) return;
    // Hand out while workers have room, to the one with the most (they fill evenly).
    while (more) {
      size_t w = 0;
      for (size_t i = 1; i < room_.size(); ++i)
        if (room_[i] > room_[w]) w = i;
      if (room_.empty() || room_[w] == 0) break;
      const std::optional<FarmTile> t = next();
      if (!t) {
        more = false;
        break;
      }
      std::vector<uint8_t> mask = mask_slice(t->range.active, t->image_width, t->rect);
      send(int(w + 1), kWork, encode_work(*t, mask));
      out_[t->index] = {*t, std::move(mask)};
      --room_[w];
      ++out;
    }
    sends_pending();  // frees what was delivered
    bool busy = false;
    while (receive(done, out)) busy = true;
    if (!busy) nap();
  }
}

}  // namespace anamorph::dist
