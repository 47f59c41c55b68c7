// The head rank's side of a render across MPI ranks: a work queue. Tiles are handed out one at a
// time to whichever worker has room (each takes four per thread, so it never waits for the next),
// and come back with their sums; the head puts them in the film or the files as a local render
// would. A queue on the head rather than static ownership plus stealing: a distorted camera's
// tile costs differ by orders of magnitude (a fisheye's corners cost nothing, a coin's region
// the most), the head has to see every tile anyway to write it, and the queue needs no second
// protocol for stealing. See docs/architecture.md, "Many machines".
#pragma once

#include <atomic>
#include <list>
#include <map>
#include <memory>
#include <vector>

#include "render/tile_farm.h"

namespace anamorph::dist {

class HeadFarm final : public TileFarm {
 public:
  // Waits until every worker has said how many tiles it takes. `cancel`: when set, run() stops
  // waiting for tiles out (a worker may have died) and returns.
  HeadFarm(std::vector<Aov> aovs, const std::atomic<bool>* cancel);
  ~HeadFarm() override;  // tells every worker to stop
  HeadFarm(const HeadFarm&) = delete;
  HeadFarm& operator=(const HeadFarm&) = delete;
  // Every worker loads this frame of the scene before its tiles are handed out.
  void begin_frame(double frame);
  void run(const std::function<std::optional<FarmTile>()>& next,
           const std::function<void(FarmResult&)>& done) override;
  int workers() const { return int(room_.size()); }

 private:
  struct Send;
  void send(int rank, int tag, std::vector<char> bytes);
  bool sends_pending();
  // One message from a worker, if any arrived; false if none.
  bool receive(const std::function<void(FarmResult&)>& done, size_t& out);
  std::vector<Aov> aovs_;
  const std::atomic<bool>* cancel_;
  std::vector<int> room_;  // tiles each worker (rank i + 1) can take now
  std::list<Send> sends_;
  // Tiles out, as handed out, with the pixels of a pass tile that travel.
  std::map<size_t, std::pair<FarmTile, std::vector<uint8_t>>> out_;
};

}  // namespace anamorph::dist
