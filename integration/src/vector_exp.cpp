#include "vector_exp.hpp"

#include <cmath>

#if defined(TASKMAP_HAVE_LIBMVEC) && defined(__SSE2__)
#include <emmintrin.h>
// glibc's libmvec: exp of two doubles (SSE2 ABI; the library picks its best variant at load).
extern "C" __m128d _ZGVbN2v_exp(__m128d);
#endif

namespace taskmap {
namespace detail {

void expBatch(const double* in, double* out, std::size_t n) {
  std::size_t k = 0;
#if defined(TASKMAP_HAVE_LIBMVEC) && defined(__SSE2__)
  for (; k + 1 < n; k += 2) _mm_storeu_pd(out + k, _ZGVbN2v_exp(_mm_loadu_pd(in + k)));
#endif
  for (; k < n; ++k) out[k] = std::exp(in[k]);
}

}  // namespace detail
}  // namespace taskmap
