#pragma once

#include <condition_variable>
#include <mutex>
#include <set>
#include <string>
#include <utility>

namespace flipflux {

/// The keys whose results threads are computing, for a memo of results that are expensive to
/// compute (the saddle-orbit memo, the certified proof memo). A thread that needs a result that
/// another thread is already computing waits for it instead of computing it a second time. If
/// that computation fails, a waiting thread then claims the key and tries in turn. The memo's
/// own mutex guards the claims too.
class key_claims {
  public:
    /// Call with `lock` held on the memo's mutex. Returns true as soon as `ready()` holds (the
    /// result is in the memo), waiting while another thread has claimed `key`. Otherwise claims
    /// `key` for the caller, returns false, and the caller computes the result and stores it.
    /// A `claim` object then gives the key back, however the computation ends.
    template <class Ready>
    bool ready_or_claim(std::unique_lock<std::mutex>& lock, const std::string& key, Ready&& ready) {
        for (;;) {
            if (ready()) return true;
            if (held_.count(key) == 0) break;
            released_.wait(lock);
        }
        held_.insert(key);
        return false;
    }

    /// Gives a claimed key back when it goes out of scope, whether the result was stored or its
    /// computation threw, and wakes the threads that wait for it.
    class claim {
      public:
        claim(key_claims& claims, std::mutex& mutex, std::string key)
            : claims_(&claims), mutex_(&mutex), key_(std::move(key)) {}
        claim(claim&& other) noexcept
            : claims_(std::exchange(other.claims_, nullptr)),
              mutex_(other.mutex_),
              key_(std::move(other.key_)) {}
        ~claim() {
            if (claims_ == nullptr) return;  // moved from
            {
                const std::lock_guard<std::mutex> lock(*mutex_);
                claims_->held_.erase(key_);
            }
            claims_->released_.notify_all();
        }
        claim(const claim&) = delete;
        claim& operator=(const claim&) = delete;
        claim& operator=(claim&&) = delete;

      private:
        key_claims* claims_;
        std::mutex* mutex_;
        std::string key_;
    };

  private:
    std::set<std::string> held_;
    std::condition_variable released_;
};

}  // namespace flipflux
