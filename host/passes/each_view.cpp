#include "passes/each_view.h"

#include <algorithm>

namespace bp {

BatchCounts EachViewPass::run(std::uint64_t first, std::uint32_t count) {
  BatchCounts total;
  for (ProgressivePass* view : views_) total += view->run(first, count);
  return total;
}

std::uint32_t EachViewPass::max_batch() const {
  std::uint32_t batch = views_.front()->max_batch();
  for (const ProgressivePass* view : views_) batch = std::min(batch, view->max_batch());
  return batch;
}

std::vector<const ProgressivePass*> EachViewPass::parts() const {
  std::vector<const ProgressivePass*> out;
  for (const ProgressivePass* view : views_)
    for (const ProgressivePass* part : view->parts()) out.push_back(part);
  return out;
}

}  // namespace bp
