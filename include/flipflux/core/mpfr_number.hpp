#pragma once

#include <mpfr.h>

namespace flipflux {

/// An MPFR number of its own precision (Boost's default precision is not involved), freed on
/// every path. For the raw-MPFR kernels that grade precision term by term (the graded Carlson
/// series, the Taylor products) and for exact decimal arithmetic at the edge (core/decimal).
class mpfr_number {
  public:
    explicit mpfr_number(mpfr_prec_t bits = MPFR_PREC_MIN) { mpfr_init2(x_, bits); }
    ~mpfr_number() { mpfr_clear(x_); }
    mpfr_number(const mpfr_number&) = delete;
    mpfr_number& operator=(const mpfr_number&) = delete;

    mpfr_ptr get() { return x_; }
    mpfr_srcptr get() const { return x_; }
    /// The number with precision p; its value is discarded when p differs from the current one.
    mpfr_ptr at(mpfr_prec_t p) {
        if (mpfr_get_prec(x_) != p) mpfr_set_prec(x_, p);
        return x_;
    }

  private:
    mpfr_t x_;
};

}  // namespace flipflux
