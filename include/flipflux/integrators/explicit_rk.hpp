// Adaptive explicit Runge-Kutta integrators with dense output, in double precision:
//   dormand_prince_5   Dormand & Prince (1980) 5(4), FSAL, 4th-order dense output (Shampine 1986)
//                      -- the method of MATLAB's ode45 and Hairer's DOPRI5;
//   dormand_prince_853 Hairer's DOP853: 8th order, error estimator combining 5th and 3rd-order
//                      embedded formulas, 7th-order dense output from 3 extra stages
//                      (Hairer, Norsett & Wanner, Solving ODEs I, 2nd ed., Sec. II.10).
// They integrate x' = f(t, x) for x in R^N forward in time and know nothing of pendulums.
//
// Error control (Hairer's, as in DOPRI5/DOP853): a step is accepted when
//     err = || e_i / sc_i ||_rms <= 1,   sc_i = atol + rtol * max(|x_i(t)|, |x_i(t+h)|),
// over the first `controlled_components` components (all by default). Leaving components out
// lets auxiliary equations (e.g. variational equations) ride along without changing the steps of
// the primary solution: the primary components are then bit-identical with or without them.
// Step-size update h_new = h * clamp(0.9 * err^(-1/q) [* err_old^beta], fac_min, fac_max), with
// q = 5, beta = 0.04 (PI control), fac in [0.2, 10] for DOPRI5 and q = 8, beta = 0, fac in
// [1/3, 6] for DOP853 (Hairer's defaults; err^(-1/8) as three square roots, not pow). The local
// error per unit step is thus kept near rtol relative to the state; the global error of a
// non-chaotic problem grows roughly linearly in time and is proportional to rtol (verified in
// tests/integrators/test_explicit_rk.cpp).
//
// Dense output: after each accepted step, dense(t) for t in [t_previous(), t()] evaluates the
// continuous extension: DOPRI5's is free (uses the step's stages), DOP853's needs 3 more
// evaluations of f, done once per step on the first call. Interpolation error: O(h^5) (DOPRI5)
// and O(h^8) (DOP853) per step, i.e. of the order of the step's local error.
//
// Outcomes are data (rk_status), not exceptions: a non-finite right-hand side or a step size that
// underflows stops the integration with a status.
//
// NOTE: the coefficients are double literals (DOP853's are irrational, published to 30 digits):
// these methods are for double only (static_assert). Higher precisions use the Gauss-Legendre
// integrator (integrators/gauss_legendre.hpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "flipflux/core/names.hpp"

namespace flipflux {

/// Options of an explicit Runge-Kutta integration.
struct rk_options {
    double rtol = 1e-10;                    ///< relative tolerance (> 0)
    double atol = 1e-10;                    ///< absolute tolerance per component (> 0)
    std::size_t controlled_components = 0;  ///< error norm over the first this many (0 = all)
    double initial_step = 0;                ///< 0: Hairer's automatic starting step
    double max_step = std::numeric_limits<double>::infinity();
    double fixed_step = 0;  ///< > 0: no error control, steps of this size (tests)
};

enum class rk_status {
    ok,                   ///< the step was accepted
    step_size_underflow,  ///< the step size fell below 16 ulp of t: the problem is too
                          ///< stiff/singular
    non_finite,           ///< the right-hand side produced NaN or infinity
};

template <>
struct enum_table<rk_status> {
    static constexpr std::string_view noun = "an integration status";
    static constexpr std::array<std::pair<rk_status, std::string_view>, 3> entries{
        {{rk_status::ok, "ok"},
         {rk_status::step_size_underflow, "step size underflow"},
         {rk_status::non_finite, "non-finite right-hand side"}}};
};

/// Dormand-Prince 5(4) with Shampine's 4th-order dense output.
struct dormand_prince_5 {
    static constexpr const char* name = "dopri5";
    static constexpr int order = 5;   // of the propagated solution
    static constexpr int stages = 7;  // including the FSAL stage f(t + h, x_new)
    static constexpr int dense_stages = 0;
    static constexpr int dense_terms = 4;
    static constexpr double beta = 0.04, fac_min = 0.2, fac_max = 10.0, safety = 0.9;
    static constexpr double c[7] = {0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1, 1};
    static constexpr double a[7][7] = {
        {},
        {1.0 / 5},
        {3.0 / 40, 9.0 / 40},
        {44.0 / 45, -56.0 / 15, 32.0 / 9},
        {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729},
        {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656},
        {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84},
    };
    // b - b_hat (5th minus 4th order), over the 7 stages
    static constexpr double e[7] = {71.0 / 57600,      0,          -71.0 / 16695, 71.0 / 1920,
                                    -17253.0 / 339200, 22.0 / 525, -1.0 / 40};
    // Shampine's dense-output coefficients
    static constexpr double d[7] = {-12715105075.0 / 11282082432.0,  0,
                                    87487479700.0 / 32700410799.0,   -10690763975.0 / 1880347072.0,
                                    701980252875.0 / 199316789632.0, -1453857185.0 / 822651844.0,
                                    69997945.0 / 29380423.0};
};

/// Hairer's DOP853 (8th order, 5th/3rd-order error estimators, 7th-order dense output).
struct dormand_prince_853 {
    static constexpr const char* name = "dop853";
    static constexpr int order = 8;
    static constexpr int stages = 13;  // 12 + the FSAL stage f(t + h, x_new)
    static constexpr int dense_stages = 3;
    static constexpr int dense_terms = 7;
    static constexpr double beta = 0.0, fac_min = 0.333, fac_max = 6.0, safety = 0.9;
    static constexpr double c[16] = {0.0,
                                     0.526001519587677318785587544488e-01,
                                     0.789002279381515978178381316732e-01,
                                     0.118350341907227396726757197510,
                                     0.281649658092772603273242802490,
                                     0.333333333333333333333333333333,
                                     0.25,
                                     0.307692307692307692307692307692,
                                     0.651282051282051282051282051282,
                                     0.6,
                                     0.857142857142857142857142857142,
                                     1.0,
                                     1.0,
                                     0.1,
                                     0.2,
                                     0.777777777777777777777777777778};
    // Row i: coefficients of stages 0..i-1 for stage i; row 12 holds the weights b (FSAL stage).
    static constexpr double a[16][16] = {
        {},
        {5.26001519587677318785587544488e-2},
        {1.97250569845378994544595329183e-2, 5.91751709536136983633785987549e-2},
        {2.95875854768068491816892993775e-2, 0, 8.87627564304205475450678981324e-2},
        {2.41365134159266685502369798665e-1, 0, -8.84549479328286085344864962717e-1,
         9.24834003261792003115737966543e-1},
        {3.7037037037037037037037037037e-2, 0, 0, 1.70828608729473871279604482173e-1,
         1.25467687566822425016691814123e-1},
        {3.7109375e-2, 0, 0, 1.70252211019544039314978060272e-1, 6.02165389804559606850219397283e-2,
         -1.7578125e-2},
        {3.70920001185047927108779319836e-2, 0, 0, 1.70383925712239993810214054705e-1,
         1.07262030446373284651809199168e-1, -1.53194377486244017527936158236e-2,
         8.27378916381402288758473766002e-3},
        {6.24110958716075717114429577812e-1, 0, 0, -3.36089262944694129406857109825,
         -8.68219346841726006818189891453e-1, 2.75920996994467083049415600797e1,
         2.01540675504778934086186788979e1, -4.34898841810699588477366255144e1},
        {4.77662536438264365890433908527e-1, 0, 0, -2.48811461997166764192642586468,
         -5.90290826836842996371446475743e-1, 2.12300514481811942347288949897e1,
         1.52792336328824235832596922938e1, -3.32882109689848629194453265587e1,
         -2.03312017085086261358222928593e-2},
        {-9.3714243008598732571704021658e-1, 0, 0, 5.18637242884406370830023853209,
         1.09143734899672957818500254654, -8.14978701074692612513997267357,
         -1.85200656599969598641566180701e1, 2.27394870993505042818970056734e1,
         2.49360555267965238987089396762, -3.0467644718982195003823669022},
        {2.27331014751653820792359768449, 0, 0, -1.05344954667372501984066689879e1,
         -2.00087205822486249909675718444, -1.79589318631187989172765950534e1,
         2.79488845294199600508499808837e1, -2.85899827713502369474065508674,
         -8.87285693353062954433549289258, 1.23605671757943030647266201528e1,
         6.43392746015763530355970484046e-1},
        {5.42937341165687622380535766363e-2, 0, 0, 0, 0, 4.45031289275240888144113950566,
         1.89151789931450038304281599044, -5.8012039600105847814672114227,
         3.1116436695781989440891606237e-1, -1.52160949662516078556178806805e-1,
         2.01365400804030348374776537501e-1, 4.47106157277725905176885569043e-2},
        {5.61675022830479523392909219681e-2, 0, 0, 0, 0, 0, 2.53500210216624811088794765333e-1,
         -2.46239037470802489917441475441e-1, -1.24191423263816360469010140626e-1,
         1.5329179827876569731206322685e-1, 8.20105229563468988491666602057e-3,
         7.56789766054569976138603589584e-3, -8.298e-3},
        {3.18346481635021405060768473261e-2, 0, 0, 0, 0, 2.83009096723667755288322961402e-2,
         5.35419883074385676223797384372e-2, -5.49237485713909884646569340306e-2, 0, 0,
         -1.08347328697249322858509316994e-4, 3.82571090835658412954920192323e-4,
         -3.40465008687404560802977114492e-4, 1.41312443674632500278074618366e-1},
        {-4.28896301583791923408573538692e-1, 0, 0, 0, 0, -4.69762141536116384314449447206,
         7.68342119606259904184240953878, 4.06898981839711007970213554331,
         3.56727187455281109270669543021e-1, 0, 0, 0, -1.39902416515901462129418009734e-3,
         2.9475147891527723389556272149, -9.15095847217987001081870187138},
    };
    // Difference of b and the 3rd-order weights (nonzero at stages 0, 8, 11).
    static constexpr double bhh0 = 0.244094488188976377952755905512,
                            bhh8 = 0.733846688281611857341361741547,
                            bhh11 = 0.220588235294117647058823529412e-1;
    // 5th-order error coefficients over stages 0..11.
    static constexpr double e5[12] = {0.1312004499419488073250102996e-1,
                                      0,
                                      0,
                                      0,
                                      0,
                                      -0.1225156446376204440720569753e1,
                                      -0.4957589496572501915214079952,
                                      0.1664377182454986536961530415e1,
                                      -0.3503288487499736816886487290,
                                      0.3341791187130174790297318841,
                                      0.8192320648511571246570742613e-1,
                                      -0.2235530786388629525884427845e-1};
    // Dense-output coefficients of the 4 highest terms, over the 16 stages.
    static constexpr double d[4][16] = {
        {-0.84289382761090128651353491142e1, 0, 0, 0, 0, 0.56671495351937776962531783590,
         -0.30689499459498916912797304727e1, 0.23846676565120698287728149680e1,
         0.21170345824450282767155149946e1, -0.87139158377797299206789907490,
         0.22404374302607882758541771650e1, 0.63157877876946881815570249290,
         -0.88990336451333310820698117400e-1, 0.18148505520854727256656404962e2,
         -0.91946323924783554000451984436e1, -0.44360363875948939664310572000e1},
        {0.10427508642579134603413151009e2, 0, 0, 0, 0, 0.24228349177525818288430175319e3,
         0.16520045171727028198505394887e3, -0.37454675472269020279518312152e3,
         -0.22113666853125306036270938578e2, 0.77334326684722638389603898808e1,
         -0.30674084731089398182061213626e2, -0.93321305264302278729567221706e1,
         0.15697238121770843886131091075e2, -0.31139403219565177677282850411e2,
         -0.93529243588444783865713862664e1, 0.35816841486394083752465898540e2},
        {0.19985053242002433820987653617e2, 0, 0, 0, 0, -0.38703730874935176555105901742e3,
         -0.18917813819516756882830838328e3, 0.52780815920542364900561016686e3,
         -0.11573902539959630126141871134e2, 0.68812326946963000169666922661e1,
         -0.10006050966910838403183860980e1, 0.77771377980534432092869265740,
         -0.27782057523535084065932004339e1, -0.60196695231264120758267380846e2,
         0.84320405506677161018159903784e2, 0.11992291136182789328035130030e2},
        {-0.25693933462703749003312586129e2, 0, 0, 0, 0, -0.15418974869023643374053993627e3,
         -0.23152937917604549567536039109e3, 0.35763911791061412378285349910e3,
         0.93405324183624310003907691704e2, -0.37458323136451633156875139351e2,
         0.10409964950896230045147246184e3, 0.29840293426660503123344363579e2,
         -0.43533456590011143754432175058e2, 0.96324553959188282948394950600e2,
         -0.39177261675615439165231486172e2, -0.14972683625798562581422125276e3},
    };
};

/// An adaptive embedded Runge-Kutta integrator of x' = f(t, x), x in R^N, with dense output.
/// F: callable as `std::array<double, N> f(double t, const std::array<double, N>& x)`.
/// Usage: construct, initialize(t0, x0), then step(t_end) repeatedly until t() == t_end; after
/// each accepted step, dense(t) interpolates on [t_previous(), t()].
template <class Method, std::size_t N, class F>
class explicit_rk {
  public:
    using state = std::array<double, N>;

    explicit explicit_rk(F f, rk_options options = {}) : f_(std::move(f)), opt_(options) {
        if (!(opt_.rtol > 0) || !(opt_.atol > 0) || !std::isfinite(opt_.rtol) ||
            !std::isfinite(opt_.atol))
            throw std::invalid_argument("explicit_rk: rtol and atol must be finite and > 0");
        if (opt_.controlled_components == 0 || opt_.controlled_components > N)
            opt_.controlled_components = N;
        if (!(opt_.max_step > 0)) throw std::invalid_argument("explicit_rk: max_step must be > 0");
    }

    /// Starts (or restarts) at (t0, x0).
    void initialize(double t0, const state& x0) {
        t_ = t_prev_ = t0;
        x_ = x_prev_ = x0;
        fx_ = f_prev_ = eval(t0, x0);
        h_last_ = 0;
        facold_ = 1e-4;
        last_rejected_ = false;
        dense_ready_ = false;
        h_ = opt_.fixed_step > 0     ? opt_.fixed_step
             : opt_.initial_step > 0 ? opt_.initial_step
                                     : initial_step();
        h_ = std::min(h_, opt_.max_step);
    }

    /// Takes one accepted step towards t_end (> t()), landing exactly on t_end when it is reached.
    rk_status step(double t_end) {
        for (;;) {
            rk_status status = rk_status::ok;
            if (!begin_step(t_end, status)) return status;
            for_each_stage([&]<int s>() { this->template stage<s>(); });
            const int r = end_step(status);
            if (r > 0) return rk_status::ok;
            if (r < 0) return status;
        }
    }

    // ---- phased stepping: step() as begin_step, stage(1) ... stage(stages - 1), end_step. Several
    // integrators advanced in lockstep, stage by stage, give the processor independent chains of
    // work (the stages of one step depend on each other); each integrator's arithmetic is exactly
    // that of step().

    /// Starts a trial step towards t_end (> t()). False (with `status`) when the step size
    /// underflowed.
    bool begin_step(double t_end, rk_status& status) {
        if (!(t_end > t_))
            throw std::invalid_argument("explicit_rk::step: t_end must lie after t()");
        double h = h_;
        bool last = false;
        if (t_ + 1.01 * h >= t_end) {
            h = t_end - t_;
            last = true;
        }
        if (!(h > 16 * std::numeric_limits<double>::epsilon() * std::abs(t_)) && !last) {
            status = rk_status::step_size_underflow;
            return false;
        }
        trial_h_ = h;
        trial_last_ = last;
        trial_end_ = t_end;
        copy(fx_.data(), k_[0]);
        return true;
    }

    /// Stage s (1 <= s < stages) of the trial step. The stage index is a template argument: the
    /// tableau row is then unrolled with its zero coefficients dropped.
    template <int s>
    void stage() {
        static_assert(s >= 1 && s < S);
        double y[N];
        stage_point_ct<s>(trial_h_, x_.data(), y);
        if constexpr (s == S - 1) copy(y, x_new_.data());
        eval_into(t_ + Method::c[s] * trial_h_, y, k_[s]);
    }

    /// The stages evaluated by the caller, several integrators at once, lane-major (vectors whose
    /// lanes are the integrators): stage s's point is stage_sum<s> from x(), derivative() (stage
    /// 0) and trial_step(), the same operations as stage<s>(), so the same bits; the caller stores
    /// f(t, y) to stage_output<s>(), and the last stage's point, the trial step's end, with
    /// set_end_point.
    double trial_step() const { return trial_h_; }
    template <int s>
    double* stage_output() {
        ++evaluations_;
        return k_[s];
    }
    void set_end_point(const double* y) { copy(y, x_new_.data()); }

    /// y = base + h sum_{j < s} a[s][j] k[j] with the tableau row known at compile time (zero
    /// terms dropped), in the order of stage<s>(), for T double or a vector of lanes (each lane
    /// the same operations as a double).
    /// (always_inline throughout, no lambda: inlined into a caller compiled for AVX2 or AVX-512,
    /// all of it is compiled for that instruction set.)
    template <int s, class T, class Stages>
    [[gnu::always_inline]] static void stage_sum(const T& h, const T* base, const Stages& k, T* y) {
        static_assert(s >= 1 && s < S);
        for (std::size_t i = 0; i < N; ++i)
            y[i] = base[i];
        add_stage_terms<s, 0>(h, k, y);
    }

    /// Calls fn.template operator()<s>() for s = 1, ..., stages - 1 in order.
    template <class Fn>
    static void for_each_stage(Fn&& fn) {
        [&]<int... s>(std::integer_sequence<int, s...>) {
            (fn.template operator()<s + 1>(), ...);
        }
        (std::make_integer_sequence<int, S - 1>{});
    }

    /// Ends the trial step: 1 accepted, 0 rejected (retry with the new step size), -1 failed
    /// (`status` says why).
    int end_step(rk_status& status) {
        return end_step(status, error_norm(trial_h_, x_.data(), x_new_.data(), k_, opt_));
    }
    /// end_step with the error norm computed by the caller (error_sums on vectors whose lanes are
    /// several integrators, from their start, end point and stages, then error_norm_from per
    /// lane: the same bits).
    int end_step(rk_status& status, double err) {
        const double h = trial_h_;
        const double tiny = 16 * std::numeric_limits<double>::epsilon() * std::abs(t_);
        if (opt_.fixed_step > 0 || err <= 1) {
            if (opt_.fixed_step > 0 || !check_ || check_(x_, x_new_)) {
                accept(h, err, trial_last_ ? trial_end_ : t_ + h);
                return 1;
            }
            // the error estimate passed but the step check failed: halve and retry
            ++rejected_;
            ++check_rejections_;
            last_rejected_ = true;
            h_ = 0.5 * h;
            if (!(h_ > tiny)) {
                status = rk_status::step_size_underflow;
                return -1;
            }
            return 0;
        }
        ++rejected_;
        last_rejected_ = true;
        if (!std::isfinite(err)) {
            h_ = h * 0.1;
            if (!(h_ > tiny)) {
                status = rk_status::non_finite;
                return -1;
            }
            return 0;
        }
        h_ = h * std::max(Method::fac_min, Method::safety * error_power(err));
        if (!(h_ > tiny)) {
            status = rk_status::step_size_underflow;
            return -1;
        }
        return 0;
    }

    /// An optional acceptance test applied after the error test: check(x_old, x_new) == false
    /// rejects the step, which is retried with half its size. For invariants the error
    /// estimate does not see, e.g. a conserved quantity that must not jump: embedded error
    /// estimates occasionally pass a step whose true error is orders of magnitude larger
    /// (DOP853's err5^2 / sqrt(err5^2 + 0.01 err3^2) when the 5th-order estimate happens to
    /// be small in every component). Not applied with fixed_step.
    void set_step_check(std::function<bool(const state&, const state&)> check) {
        check_ = std::move(check);
    }
    /// Steps rejected by the step check (included in rejected_steps()).
    long check_rejections() const { return check_rejections_; }

    /// Integrates to t_end, calling observer(*this) after every accepted step.
    template <class Observer>
    rk_status integrate(double t_end, Observer&& observer) {
        while (t_ < t_end) {
            const rk_status s = step(t_end);
            if (s != rk_status::ok) return s;
            observer(*this);
        }
        return rk_status::ok;
    }

    /// The continuous extension of the last accepted step at t in [t_previous(), t()].
    state dense(double t) {
        if (!dense_ready_) prepare_dense();
        const double th = h_last_ == 0 ? 0 : (t - t_prev_) / h_last_;
        const double th1 = 1 - th;
        state y;
        double* yp = y.data();
        const double* x0 = x_prev_.data();
        for (std::size_t i = 0; i < N; ++i) {
            // y0 + th (r0 + th1 (r1 + th (r2 + th1 (r3 + th (r4 + th1 (r5 + th r6))))))
            double acc = rc_[Method::dense_terms - 1][i];
            for (int j = Method::dense_terms - 2; j >= 0; --j)
                acc = rc_[j][i] + ((j % 2 == 0) ? th1 : th) * acc;
            yp[i] = x0[i] + th * acc;
        }
        return y;
    }

    /// Adds delta to the current state (and to the last step's start, keeping the dense output
    /// valid). Only for directions in which f is invariant (e.g. angles shifted by 2 pi).
    void translate(const state& delta) {
        for (std::size_t i = 0; i < N; ++i) {
            x_[i] += delta[i];
            x_prev_[i] += delta[i];
        }
    }

    /// Multiplies the components i >= first by `factor` everywhere (current state, last step,
    /// stages, dense output), e.g. to renormalise a tangent vector. Valid only for components
    /// whose equations are linear and homogeneous in themselves and do not feed back into the
    /// components below `first` (variational equations): then the integration continues exactly
    /// as if the tail had been scaled from the start.
    void rescale_tail(std::size_t first, double factor) {
        auto scale_tail = [&](double* v) {
            for (std::size_t i = first; i < N; ++i)
                v[i] *= factor;
        };
        scale_tail(x_.data());
        scale_tail(x_prev_.data());
        scale_tail(x_new_.data());
        scale_tail(fx_.data());
        scale_tail(f_prev_.data());
        for (auto& k : k_)
            scale_tail(k);
        for (auto& r : rc_)
            scale_tail(r);
    }

    double t() const { return t_; }
    double t_previous() const { return t_prev_; }
    const state& x() const { return x_; }
    const state& x_previous() const { return x_prev_; }
    const state& derivative() const { return fx_; }               ///< f(t, x)
    const state& derivative_previous() const { return f_prev_; }  ///< at the last step's start
    double last_step() const { return h_last_; }
    double next_step() const { return h_; }
    long accepted_steps() const { return accepted_; }
    long rejected_steps() const { return rejected_; }
    long evaluations() const { return evaluations_; }
    const F& rhs() const { return f_; }
    const rk_options& options() const { return opt_; }

  private:
    // NOTE: the inner loops index raw arrays (C-array tableaux and stage storage, pointers from
    // data()): the same code at -O2, and several times faster in the -O0 coverage build, where
    // every std::array::operator[] is a function call.
    static constexpr int S = Method::stages;
    static constexpr int SD = Method::stages + Method::dense_stages;

    static void copy(const double* from, double* to) {
        for (std::size_t i = 0; i < N; ++i)
            to[i] = from[i];
    }
    void eval_into(double t, const double* x, double* out) {
        ++evaluations_;
        state xs;
        copy(x, xs.data());
        const state f = f_(t, xs);
        copy(f.data(), out);
    }
    state eval(double t, const state& x) {
        ++evaluations_;
        return f_(t, x);
    }

    // Hairer's hinit: h with h^order * ||f''|| ~ 0.01, capped by 100 times the explicit-Euler
    // guess.
    double initial_step() {
        const std::size_t m = opt_.controlled_components;
        double d0 = 0, d1 = 0;
        for (std::size_t i = 0; i < m; ++i) {
            const double sc = opt_.atol + opt_.rtol * std::abs(x_[i]);
            d0 += (x_[i] / sc) * (x_[i] / sc);
            d1 += (fx_[i] / sc) * (fx_[i] / sc);
        }
        d0 = std::sqrt(d0 / m);
        d1 = std::sqrt(d1 / m);
        double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
        h0 = std::min(h0, opt_.max_step);
        state x1;
        for (std::size_t i = 0; i < N; ++i)
            x1[i] = x_[i] + h0 * fx_[i];
        const state f1 = eval(t_ + h0, x1);
        double d2 = 0;
        for (std::size_t i = 0; i < m; ++i) {
            const double sc = opt_.atol + opt_.rtol * std::abs(x_[i]);
            d2 += ((f1[i] - fx_[i]) / sc) * ((f1[i] - fx_[i]) / sc);
        }
        d2 = std::sqrt(d2 / m) / h0;
        const double dm = std::max(d1, d2);
        const double h1 =
            dm <= 1e-15 ? std::max(1e-6, h0 * 1e-3) : std::pow(0.01 / dm, 1.0 / Method::order);
        const double h = std::min(100 * h0, h1);
        return std::isfinite(h) && h > 0 ? h : 1e-6;
    }

    // stage_point with the row known at compile time (same arithmetic, zero terms dropped)
    template <int s>
    void stage_point_ct(double h, const double* base, double* y) const {
        stage_sum<s>(h, base, k_, y);
    }
    // the terms j, j + 1, ..., s - 1 of stage_sum<s>
    template <int s, int j, class T, class Stages>
    [[gnu::always_inline]] static void add_stage_terms(const T& h, const Stages& k, T* y) {
        constexpr double a = Method::a[s][j];
        if constexpr (a != 0) {
            for (std::size_t i = 0; i < N; ++i)
                y[i] += h * a * k[j][i];
        }
        if constexpr (j + 1 < s) add_stage_terms<s, j + 1>(h, k, y);
    }

    // y = base + h sum_{j < s} a[s][j] k_j
    void stage_point(int s, double h, const double* base, double* y) const {
        copy(base, y);
        for (int j = 0; j < s; ++j) {
            const double a = Method::a[s][j];
            if (a == 0) continue;
            const double* kj = k_[j];
            for (std::size_t i = 0; i < N; ++i)
                y[i] += h * a * kj[i];
        }
    }

  public:
    /// The embedded error estimate's norm over the controlled components (Hairer's: DOP853's
    /// |h| s5 / sqrt((s5 + 0.01 s3) m) with s5, s3 the sums of squares of the scaled 5th- and
    /// 3rd-order estimates, DOPRI5's RMS of h e / sc) from a step h
    /// with stages k from x0 to x1, in two parts: error_sums, the sums over components, for T
    /// double or a vector whose lanes are several integrators (vector operations then, each
    /// lane's the same as a double's), and error_norm_from, one integrator's norm from its sums.
    /// (always_inline: see stage_sum.)
    template <class T, class Stages>
    [[gnu::always_inline]] static void error_sums(const T& h, const T* x0, const T* x1,
                                                  const Stages& k, const rk_options& o, T& first,
                                                  T& second) {
        const std::size_t m = o.controlled_components;
        first = T{};  // DOP853: s5, s3; DOPRI5: the sum of squares of h e / sc, and 0
        second = T{};
        for (std::size_t i = 0; i < m; ++i) {
            T sc;
            if constexpr (std::is_floating_point_v<T>) {
                sc = o.atol + o.rtol * std::max(std::abs(x0[i]), std::abs(x1[i]));
            } else {
                // lane by lane the same: |-0| = -0 here gives the same scale (atol + rtol * -0),
                // and a < b ? b : a is std::max's rule
                const T a = x0[i] < T{} ? -x0[i] : x0[i], b = x1[i] < T{} ? -x1[i] : x1[i];
                sc = o.atol + o.rtol * (a < b ? b : a);
            }
            if constexpr (Method::order == 5) {
                T e{};
                for (int j = 0; j < S; ++j)
                    e += Method::e[j] * k[j][i];
                const T r = h * e / sc;
                first += r * r;
            } else {
                T e5{}, e3{};
                for (int j = 0; j < 12; ++j) {
                    e5 += Method::e5[j] * k[j][i];
                    e3 += Method::a[12][j] * k[j][i];
                }
                e3 -= Method::bhh0 * k[0][i] + Method::bhh8 * k[8][i] + Method::bhh11 * k[11][i];
                first += (e5 / sc) * (e5 / sc);
                second += (e3 / sc) * (e3 / sc);
            }
        }
    }
    static double error_norm_from(double h, double first, double second, const rk_options& o) {
        const auto m = static_cast<double>(o.controlled_components);
        if constexpr (Method::order == 5) {
            return std::sqrt(first / m);
        } else {
            if (first == 0 && second == 0) return 0;
            double deno = first + 0.01 * second;
            if (!(deno > 0)) deno = 1;
            return std::abs(h) * first / std::sqrt(deno * m);
        }
    }

  private:
    template <class Stages>
    static double error_norm(double h, const double* x0, const double* x1, const Stages& k,
                             const rk_options& o) {
        double first, second;
        error_sums(h, x0, x1, k, o, first, second);
        return error_norm_from(h, first, second, o);
    }
    // err^(-1/q + 0.75 beta) of the step-size update; for DOP853 (q = 8, beta = 0) as
    // 1 / sqrt(sqrt(sqrt(err))): correctly rounded square roots, a few ulp from pow's value (the
    // factor is clamped to [1/3, 6] anyway) at a fifth of its cost.
    static double error_power(double err) {
        if constexpr (Method::order == 8 && Method::beta == 0)
            return 1 / std::sqrt(std::sqrt(std::sqrt(err)));
        else
            return std::pow(err, -1.0 / Method::order + 0.75 * Method::beta);
    }

    void accept(double h, double err, double t_new) {
        ++accepted_;
        double fac = 1;
        if (opt_.fixed_step > 0) {
            h_ = opt_.fixed_step;
        } else {
            const double e = std::max(err, 1e-300);
            // PI control: h_new = h * safety * err^-(1/q - 0.75 beta) * err_old^beta
            fac = Method::safety * error_power(e);
            if constexpr (Method::beta != 0) fac *= std::pow(facold_, Method::beta);
            fac = std::clamp(fac, Method::fac_min, Method::fac_max);
            facold_ = std::max(err, 1e-4);
            double h_new = h * fac;
            if (last_rejected_) h_new = std::min(h_new, h);
            h_ = std::min(h_new, opt_.max_step);
        }
        last_rejected_ = false;
        t_prev_ = t_;
        x_prev_ = x_;
        f_prev_ = fx_;
        t_ = t_new;
        x_ = x_new_;
        copy(k_[S - 1], fx_.data());
        h_last_ = h;
        dense_ready_ = false;
    }

    void prepare_dense() {
        const double h = h_last_;
        const double* x0 = x_prev_.data();
        const double* x1 = x_.data();
        if constexpr (Method::order == 5) {
            // k_ holds the stages of the accepted step (k_[6] = f at its end).
            // Shampine's form: y0 + th (r0 + th1 (r1 + th (r2 + th1 r3))).
            for (std::size_t i = 0; i < N; ++i) {
                const double dx = x1[i] - x0[i];
                const double bspl = h * k_[0][i] - dx;
                rc_[0][i] = dx;
                rc_[1][i] = bspl;
                rc_[2][i] = dx - h * k_[6][i] - bspl;
                double sum = 0;
                for (int j = 0; j < 7; ++j)
                    sum += Method::d[j] * k_[j][i];
                rc_[3][i] = h * sum;
            }
        } else {
            double y[N];
            for (int s = 13; s < 16; ++s) {
                stage_point(s, h, x0, y);
                eval_into(t_prev_ + Method::c[s] * h, y, k_[s]);
            }
            for (std::size_t i = 0; i < N; ++i) {
                const double dx = x1[i] - x0[i];
                rc_[0][i] = dx;
                rc_[1][i] = h * k_[0][i] - dx;
                rc_[2][i] = 2 * dx - h * (k_[12][i] + k_[0][i]);
                for (int r = 0; r < 4; ++r) {
                    double sum = 0;
                    for (int j = 0; j < 16; ++j)
                        sum += Method::d[r][j] * k_[j][i];
                    rc_[3 + r][i] = h * sum;
                }
            }
        }
        dense_ready_ = true;
    }

    F f_;
    rk_options opt_;
    double t_ = 0, t_prev_ = 0, h_ = 0, h_last_ = 0, facold_ = 1e-4;
    double trial_h_ = 0, trial_end_ = 0;
    bool trial_last_ = false;
    bool last_rejected_ = false, dense_ready_ = false;
    state x_{}, x_prev_{}, x_new_{}, fx_{}, f_prev_{};
    double k_[SD][N] = {};
    double rc_[Method::dense_terms][N] = {};
    long accepted_ = 0, rejected_ = 0, evaluations_ = 0, check_rejections_ = 0;
    std::function<bool(const state&, const state&)> check_;

    static_assert(Method::stages + Method::dense_stages >= 7);
};

}  // namespace flipflux
