// What the three random-walk table generators (ggx_multiple_gen, ggx_glass_gen, ggx_aniso_gen) share:
// their command line and running their rows on all cores.
//
//   GENERATOR OUT.inc [WALKS [ROW]]   (WALKS 0: the generator's default, the committed table's)
//
// writes the whole table; with ROW it walks that row only (a slice, cheap) and prints every number of
// the other rows as nan, so that tools/check_walk_table.py can compare the slice with the table
// committed under engine/scene/tables/ (the build reads that one: regenerating it costs minutes of CPU).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <thread>
#include <vector>

namespace smis::walk_rows {

struct Args {
    const char* out = nullptr;
    long walks = 0;
    int only = -1;  // the row of a slice, -1: every row
};

// Parses the command line; false (after printing the usage) when it is wrong.
inline bool parse(int argc, char** argv, const char* name, long default_walks, Args* args) {
    if (argc < 2 || argc > 4) {
        std::fprintf(stderr, "usage: %s OUT.inc [WALKS [ROW]]\n", name);
        return false;
    }
    args->out = argv[1];
    args->walks = argc > 2 ? std::atol(argv[2]) : 0;
    if (args->walks <= 0) args->walks = default_walks;  // 0: the table's own count
    args->only = argc > 3 ? std::atoi(argv[3]) : -1;
    return true;
}

constexpr double kNotWalked = std::numeric_limits<double>::quiet_NaN();

// Marks every number of the containers not walked.
template <class... Containers>
void mark_not_walked(Containers&... containers) {
    (std::fill(std::begin(containers), std::end(containers), kNotWalked), ...);
}

// make(k) for the rows k in [0, count) (or only args.only), spread over all cores; a row not walked is
// `unwalked` (its numbers nan).
template <class Row, class Make>
std::vector<Row> run(int count, const Args& args, const Row& unwalked, Make&& make) {
    std::vector<Row> rows(size_t(count), unwalked);
    std::vector<std::thread> threads;
    unsigned n = std::max(1u, std::thread::hardware_concurrency());
    for (unsigned t = 0; t < n; ++t)
        threads.emplace_back([&, t] {
            for (int k = int(t); k < count; k += int(n))
                if (args.only < 0 || k == args.only) rows[size_t(k)] = make(k);
        });
    for (std::thread& t : threads) t.join();
    return rows;
}

}  // namespace smis::walk_rows
