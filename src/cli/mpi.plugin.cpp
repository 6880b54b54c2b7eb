// The MPI plugin, libflipflux_mpi.so (mpi_group.hpp): MPI_COMM_WORLD as a process_group. It
// calls nothing of flipflux (process_group's members are all inline or pure).
#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "mpi_group.hpp"

namespace flipflux::cli {
namespace {

/// MPI_COMM_WORLD through Open MPI.
class open_mpi final : public mpi_group {
  public:
    open_mpi() {
        int provided = 0;
        MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
    }
    ~open_mpi() override { MPI_Finalize(); }
    open_mpi(const open_mpi&) = delete;
    open_mpi& operator=(const open_mpi&) = delete;
    int rank() const override { return rank_; }
    int size() const override { return size_; }
    std::string broadcast(const std::string& text) override {
        unsigned long long n = text.size();
        MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
        std::string out = rank_ == 0 ? text : std::string(n, '\0');
        for (unsigned long long done = 0; done < n;) {  // in pieces below INT_MAX
            const int piece = static_cast<int>(std::min<unsigned long long>(n - done, 1u << 30));
            MPI_Bcast(out.data() + done, piece, MPI_CHAR, 0, MPI_COMM_WORLD);
            done += static_cast<unsigned long long>(piece);
        }
        return out;
    }
    std::vector<std::string> gather(const std::string& text) override {
        std::vector<std::string> out;
        if (rank_ == 0) {
            out.resize(static_cast<std::size_t>(size_));
            out[0] = text;
            for (int r = 1; r < size_; ++r)
                out[static_cast<std::size_t>(r)] = receive(r);
        } else {
            send(text);
        }
        return out;
    }
    bool any(bool flag) override {
        int mine = flag ? 1 : 0, all = 0;
        MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
        return all != 0;
    }
    [[noreturn]] void abort(int status) override {
        MPI_Abort(MPI_COMM_WORLD, status);
        std::_Exit(status);
    }

  private:
    void send(const std::string& text) {
        unsigned long long n = text.size();
        MPI_Send(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, 0, MPI_COMM_WORLD);
        for (unsigned long long done = 0; done < n;) {
            const int piece = static_cast<int>(std::min<unsigned long long>(n - done, 1u << 30));
            MPI_Send(text.data() + done, piece, MPI_CHAR, 0, 1, MPI_COMM_WORLD);
            done += static_cast<unsigned long long>(piece);
        }
    }
    std::string receive(int from) {
        unsigned long long n = 0;
        MPI_Recv(&n, 1, MPI_UNSIGNED_LONG_LONG, from, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        std::string text(n, '\0');
        for (unsigned long long done = 0; done < n;) {
            const int piece = static_cast<int>(std::min<unsigned long long>(n - done, 1u << 30));
            MPI_Recv(text.data() + done, piece, MPI_CHAR, from, 1, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
            done += static_cast<unsigned long long>(piece);
        }
        return text;
    }
    int rank_ = 0, size_ = 1;
};

}  // namespace
}  // namespace flipflux::cli

/// The plugin's one symbol: MPI initialised (the caller owns the object).
extern "C" __attribute__((visibility("default"))) flipflux::cli::mpi_group*
flipflux_mpi_group_open() {
    return new flipflux::cli::open_mpi();
}
