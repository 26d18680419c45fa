// One header, two compilers: this file lets kernels/shared/*.h compile as OpenCL C 1.2 (device)
// and as C++20 (host unit tests), so sampling, BRDF and weight code is tested where it runs.
#ifndef BP_SHARED_COMPAT_H
#define BP_SHARED_COMPAT_H

#ifdef __OPENCL_C_VERSION__
// ---------------------------------------------------------------- OpenCL C
#define BP_FN static inline
#define BP_GLOBAL __global
#define BP_CONSTANT __constant
typedef uint bp_u32;
typedef int bp_i32;
typedef ulong bp_u64;
#define make_float3(x, y, z) ((float3)((x), (y), (z)))
BP_FN bp_u32 bp_mulhi(bp_u32 a, bp_u32 b) { return mul_hi(a, b); }
#define BP_FLOAT_MAX FLT_MAX
#define BP_ISFINITE(x) isfinite(x)
#define BP_ALIGN(n) __attribute__((aligned(n)))
// Hot helpers that must inline (PoCL otherwise keeps some as calls, with their arrays in memory).
#define BP_INLINE static inline __attribute__((always_inline))
// Prefetch of one cache line; PoCL's prefetch() builtin does nothing, clang's builtin does.
#ifdef __clang__
#define BP_PREFETCH(p) __builtin_prefetch(p)
#else
#define BP_PREFETCH(p) prefetch((p), 1)
#endif
// 4-wide float (SIMD box tests in bvh.h): lanes by constant index, loads of 4 consecutive floats.
typedef float4 bp_float4;
#define BP_LANE(v, i) ((v).s##i)
#define bp_load4(p) vload4(0, (p))
BP_FN bp_float4 bp_splat4(float x) { return (float4)(x); }
BP_FN bp_float4 bp_min4(bp_float4 a, bp_float4 b) { return a < b ? a : b; }  // no NaN care: minps
BP_FN bp_float4 bp_max4(bp_float4 a, bp_float4 b) { return a > b ? a : b; }

#else
// ---------------------------------------------------------------- C++ host
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cfloat>
#include <cstring>
#define BP_FN inline
#define BP_GLOBAL
#define BP_CONSTANT
#define BP_LOAD3_IS_GENERIC 1
typedef std::uint32_t bp_u32;
typedef std::int32_t bp_i32;
typedef std::uint64_t bp_u64;
inline bp_u32 bp_mulhi(bp_u32 a, bp_u32 b) { return bp_u32((bp_u64(a) * bp_u64(b)) >> 32); }
#define BP_FLOAT_MAX FLT_MAX
#define BP_ISFINITE(x) std::isfinite(x)

#define BP_ALIGN(n) alignas(n)
#define BP_INLINE inline __attribute__((always_inline))
#define BP_PREFETCH(p) __builtin_prefetch(p)
// float4 as OpenCL C sees it for bvh.h's box tests: GCC/Clang vector extension, SSE on x86.
typedef float bp_float4 __attribute__((vector_size(16)));
#define BP_LANE(v, i) ((v)[i])
inline bp_float4 bp_load4(const float* p) { bp_float4 v; std::memcpy(&v, p, sizeof v); return v; }
inline bp_float4 bp_splat4(float x) { return bp_float4{x, x, x, x}; }
inline bp_float4 bp_min4(bp_float4 a, bp_float4 b) { return a < b ? a : b; }
inline bp_float4 bp_max4(bp_float4 a, bp_float4 b) { return a > b ? a : b; }

using std::acos; using std::cos; using std::exp; using std::fabs; using std::floor; using std::fmax;
using std::fmin; using std::log; using std::log1p; using std::expm1; using std::pow; using std::sin;
using std::sqrt; using std::ceil; using std::atan2;

// float3 as OpenCL C sees it, for the arithmetic that shared code does.
struct float3 { float x, y, z; };
inline float3 make_float3(float x, float y, float z) { return float3{x, y, z}; }
inline float3 operator+(float3 a, float3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline float3 operator-(float3 a, float3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline float3 operator-(float3 a) { return {-a.x, -a.y, -a.z}; }
inline float3 operator*(float3 a, float3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline float3 operator*(float3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline float3 operator*(float s, float3 a) { return {a.x * s, a.y * s, a.z * s}; }
inline float3 operator/(float3 a, float s) { return {a.x / s, a.y / s, a.z / s}; }
inline float3& operator+=(float3& a, float3 b) { a = a + b; return a; }
inline float3& operator*=(float3& a, float3 b) { a = a * b; return a; }
inline float3& operator*=(float3& a, float s) { a = a * s; return a; }
inline float dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float3 cross(float3 a, float3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(float3 a) { return std::sqrt(dot(a, a)); }
inline float3 normalize(float3 a) { return a * (1.0f / length(a)); }
inline float clamp(float x, float lo, float hi) { return std::min(std::max(x, lo), hi); }
inline float3 fmax(float3 a, float3 b) { return {std::fmax(a.x, b.x), std::fmax(a.y, b.y), std::fmax(a.z, b.z)}; }
inline float3 fmin(float3 a, float3 b) { return {std::fmin(a.x, b.x), std::fmin(a.y, b.y), std::fmin(a.z, b.z)}; }
#endif

// Feature switches (host/device/kernel_features.h): the host builds each program with only what the
// render uses; the generic build, and every host compile of this code, has them all.
#ifndef BP_FEATURE_PHONG
#define BP_FEATURE_PHONG 1
#endif
#ifndef BP_FEATURE_GGX
#define BP_FEATURE_GGX 1
#endif
#ifndef BP_FEATURE_LIGHT_SAMPLING
#define BP_FEATURE_LIGHT_SAMPLING 1
#endif
#ifndef BP_FEATURE_SHADING_NORMALS
#define BP_FEATURE_SHADING_NORMALS 1
#endif
#ifndef BP_FEATURE_TEXTURES
#define BP_FEATURE_TEXTURES 1
#endif
#ifndef BP_FEATURE_NORMAL_MAPS
#define BP_FEATURE_NORMAL_MAPS 1
#endif
#ifndef BP_FEATURE_ENVIRONMENT
#define BP_FEATURE_ENVIRONMENT 1
#endif
#ifndef BP_FEATURE_TRANSMISSION
#define BP_FEATURE_TRANSMISSION 1
#endif

#define BP_PI 3.14159265358979323846f
#define BP_TWO_PI 6.28318530717958647692f
#define BP_INV_PI 0.31830988618379067154f

BP_FN float3 bp_load3(BP_GLOBAL const float* p) { return make_float3(p[0], p[1], p[2]); }
#ifdef BP_LOAD3_IS_GENERIC
#define bp_private3 bp_load3
#else
// The same from private memory (kernel arguments passed by value); OpenCL 1.2 has no generic space.
BP_FN float3 bp_private3(const float* p) { return make_float3(p[0], p[1], p[2]); }
#endif
BP_FN float bp_max3(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }

#endif  // BP_SHARED_COMPAT_H
