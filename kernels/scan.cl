// Exclusive prefix sum of n uints in three launches without local memory or barriers (chunks
// summed sequentially: cheap on CPUs, adequate on GPUs for the sizes here):
//   scan_chunk_totals (one work-item per chunk) -> scan_totals (one work-item) -> scan_chunks.
// offsets holds n + 1 entries; offsets[n] is the total.

__kernel void scan_chunk_totals(__global const uint* values, const uint n, const uint chunk,
                                __global uint* totals) {
  uint c = (uint)get_global_id(0);
  uint begin = c * chunk;
  if (begin >= n) return;
  uint end = min(begin + chunk, n), sum = 0u;
  for (uint i = begin; i < end; ++i) sum += values[i];
  totals[c] = sum;
}

__kernel void scan_totals(__global uint* totals, const uint chunks) {
  if (get_global_id(0) != 0) return;
  uint sum = 0u;
  for (uint c = 0; c < chunks; ++c) {
    uint t = totals[c];
    totals[c] = sum;
    sum += t;
  }
  totals[chunks] = sum;
}

__kernel void scan_chunks(__global const uint* values, const uint n, const uint chunk,
                          __global const uint* totals, __global uint* offsets) {
  uint c = (uint)get_global_id(0);
  uint begin = c * chunk;
  if (begin >= n) return;
  uint end = min(begin + chunk, n), sum = totals[c];
  for (uint i = begin; i < end; ++i) {
    uint v = values[i];
    offsets[i] = sum;
    sum += v;
  }
  if (end == n) offsets[n] = sum;  // the total, so offsets[i + 1] - offsets[i] works for the last i
}
