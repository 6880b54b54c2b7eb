#pragma once

namespace flipflux {

/// Sets a flag while it lives and restores the flag's previous value when it dies: the RAII base
/// of the thread-local switches (saddle_orbit_memo_bypass, certified_proof_memo_bypass), whose
/// flags are thread_local variables of their own units.
class scoped_flag {
  public:
    explicit scoped_flag(bool& flag) : flag_(flag), previous_(flag) { flag_ = true; }
    ~scoped_flag() { flag_ = previous_; }
    scoped_flag(const scoped_flag&) = delete;
    scoped_flag& operator=(const scoped_flag&) = delete;

  private:
    bool& flag_;
    bool previous_;
};

}  // namespace flipflux
