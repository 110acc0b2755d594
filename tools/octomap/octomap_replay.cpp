// SPDX-License-Identifier: MIT
// A readings.csv mapped by OctoMap, each sonar reading a fan of rays across its cone, and
// written as a trinary PGM on the firmware's grid: the peer that `make compare` scores.
//
// The map is 2-D at the sensor's height: every ray lies in the one layer of voxels whose
// centre is z = L/2. World points are shifted by the grid's origin first, so OctoMap's
// voxel (32768 + a, 32768 + b) is the firmware's cell (a, b) exactly.
#include <octomap/OcTree.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

constexpr int kExitUsage = 2;
constexpr double kPi = 3.14159265358979323846;
constexpr unsigned kKeyCentre = 32768u; // OctoMap's key of the cell at coordinate 0
constexpr unsigned char kOccupied = 0u, kFree = 254u, kUnknown = 205u; // mapexport.h

struct Options {
    const char *readings = nullptr;
    const char *out = nullptr;
    unsigned a = 0, b = 0;         // grid cells along x, y
    double origin_x = 0.0, origin_y = 0.0, cell_m = 0.0;
    double mount_x = 0.0, mount_y = 0.0, mount_yaw_deg = 0.0;
    bool true_poses = true;        // the true_* columns (else odom_*)
    double max_range_m = 1.0;      // echoes beyond: free rays this long, no hit
    double min_range_m = 0.02;     // echoes below: not trusted, skipped (the firmware's)
    double cone_deg = 15.0;        // full width of the fan
    unsigned rays = 0;             // 0: rays one cell apart at the range
    double prob_hit = 0.7, prob_miss = 0.4, clamp_min = 0.1192, clamp_max = 0.971;
    bool timeout_free = false;     // a timeout as free rays of max_range_m (else skipped)
    bool lazy = false;             // OctoMap's lazy_eval: inner nodes updated once at the end
    bool discretize = false;       // OctoMap's discretize: one ray per endpoint cell
};

[[noreturn]] void usage_error(const std::string &msg)
{
    std::fprintf(stderr, "octomap_replay: %s (see --help)\n", msg.c_str());
    std::exit(kExitUsage);
}

void usage()
{
    std::puts(
        "usage: octomap_replay --readings FILE --out MAP.pgm --grid A B ORIGIN_X ORIGIN_Y CELL_M\n"
        "                      [--mount X_M Y_M YAW_DEG] [--poses true|odom]\n"
        "                      [--max-range M] [--min-range M] [--cone DEG] [--rays N]\n"
        "                      [--hit P] [--miss P] [--clamp MIN MAX] [--timeouts skip|free]\n"
        "                      [--lazy] [--discretize]\n"
        "Maps a readings.csv with OctoMap: each reading a fan of --rays rays (0: one cell\n"
        "apart at the range) across a --cone of DEG, inserted as one point cloud from the\n"
        "sonar; echoes beyond --max-range are free rays of that length. Writes a trinary PGM\n"
        "(0 occupied, 254 free, 205 unknown) on the grid, first row the largest y.\n"
        "--lazy and --discretize are insertPointCloud's lazy_eval and discretize. The work\n"
        "of insertion is all in functions named insert_reading* (for callgrind).");
}

double number(const char *opt, const char *s, double lo, double hi)
{
    char *end = nullptr;
    errno = 0;
    double v = std::strtod(s, &end);
    if (end == s || *end != '\0' || errno != 0 || !std::isfinite(v) || v < lo || v > hi) {
        usage_error(std::string(opt) + ": '" + s + "' is not a number from " +
                    std::to_string(lo) + " to " + std::to_string(hi));
    }
    return v;
}

Options parse(int argc, char **argv)
{
    Options o;
    auto need = [&](int i, int n, const char *opt) {
        if (i + n >= argc) {
            usage_error(std::string(opt) + " needs " + std::to_string(n) + " value(s)");
        }
    };
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!std::strcmp(a, "--help")) {
            usage();
            std::exit(0);
        } else if (!std::strcmp(a, "--readings")) {
            need(i, 1, a);
            o.readings = argv[++i];
        } else if (!std::strcmp(a, "--out")) {
            need(i, 1, a);
            o.out = argv[++i];
        } else if (!std::strcmp(a, "--grid")) {
            need(i, 5, a);
            o.a = (unsigned)number(a, argv[++i], 1, 4096);
            o.b = (unsigned)number(a, argv[++i], 1, 4096);
            o.origin_x = number(a, argv[++i], -1e4, 1e4);
            o.origin_y = number(a, argv[++i], -1e4, 1e4);
            o.cell_m = number(a, argv[++i], 0.001, 10.0);
        } else if (!std::strcmp(a, "--mount")) {
            need(i, 3, a);
            o.mount_x = number(a, argv[++i], -1.0, 1.0);
            o.mount_y = number(a, argv[++i], -1.0, 1.0);
            o.mount_yaw_deg = number(a, argv[++i], -180.0, 180.0);
        } else if (!std::strcmp(a, "--poses")) {
            need(i, 1, a);
            std::string v = argv[++i];
            if (v != "true" && v != "odom") {
                usage_error("--poses: '" + v + "' is neither true nor odom");
            }
            o.true_poses = v == "true";
        } else if (!std::strcmp(a, "--max-range")) {
            need(i, 1, a);
            o.max_range_m = number(a, argv[++i], 0.01, 100.0);
        } else if (!std::strcmp(a, "--min-range")) {
            need(i, 1, a);
            o.min_range_m = number(a, argv[++i], 0.0, 10.0);
        } else if (!std::strcmp(a, "--cone")) {
            need(i, 1, a);
            o.cone_deg = number(a, argv[++i], 0.0, 90.0);
        } else if (!std::strcmp(a, "--rays")) {
            need(i, 1, a);
            o.rays = (unsigned)number(a, argv[++i], 0, 1000);
        } else if (!std::strcmp(a, "--hit")) {
            need(i, 1, a);
            o.prob_hit = number(a, argv[++i], 0.5, 0.999);
        } else if (!std::strcmp(a, "--miss")) {
            need(i, 1, a);
            o.prob_miss = number(a, argv[++i], 0.001, 0.5);
        } else if (!std::strcmp(a, "--clamp")) {
            need(i, 2, a);
            o.clamp_min = number(a, argv[++i], 0.001, 0.5);
            o.clamp_max = number(a, argv[++i], 0.5, 0.999);
        } else if (!std::strcmp(a, "--timeouts")) {
            need(i, 1, a);
            std::string v = argv[++i];
            if (v != "skip" && v != "free") {
                usage_error("--timeouts: '" + v + "' is neither skip nor free");
            }
            o.timeout_free = v == "free";
        } else if (!std::strcmp(a, "--lazy")) {
            o.lazy = true;
        } else if (!std::strcmp(a, "--discretize")) {
            o.discretize = true;
        } else {
            usage_error(std::string("unknown option '") + a + "'");
        }
    }
    if (o.readings == nullptr || o.out == nullptr || o.a == 0) {
        usage_error("--readings, --out and --grid are required");
    }
    return o;
}

struct Reading {
    double servo_deg, range_m, x, y, th;
    bool echo;
};

std::vector<std::string> split(const std::string &line)
{
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string s;
    while (std::getline(ss, s, ',')) {
        f.push_back(s);
    }
    if (!line.empty() && line.back() == ',') {
        f.emplace_back();
    }
    return f;
}

// Every reading of the log; a malformed one names the file and line and exits 2.
std::vector<Reading> load(const Options &o)
{
    std::ifstream in(o.readings);
    if (!in) {
        usage_error(std::string(o.readings) + ": cannot open: " + std::strerror(errno));
    }
    std::string line;
    std::getline(in, line);
    std::vector<std::string> head = split(line);
    const char *names[] = {"servo_deg", "range_m", "status",
                           o.true_poses ? "true_x_m" : "odom_x_m",
                           o.true_poses ? "true_y_m" : "odom_y_m",
                           o.true_poses ? "true_th_rad" : "odom_th_rad"};
    size_t col[6];
    for (int k = 0; k < 6; k++) {
        col[k] = head.size();
        for (size_t i = 0; i < head.size(); i++) {
            if (head[i] == names[k]) {
                col[k] = i;
            }
        }
        if (col[k] == head.size()) {
            usage_error(std::string(o.readings) + ":1: no column " + names[k]);
        }
    }
    std::vector<Reading> rows;
    unsigned lineno = 1;
    while (std::getline(in, line)) {
        lineno++;
        std::vector<std::string> f = split(line);
        auto bad = [&](const char *what) {
            usage_error(std::string(o.readings) + ":" + std::to_string(lineno) + ": " + what);
        };
        for (size_t c : col) {
            if (c >= f.size()) {
                bad("too few columns");
            }
        }
        auto num = [&](size_t c) {
            char *end = nullptr;
            double v = std::strtod(f[c].c_str(), &end);
            if (f[c].empty() || *end != '\0' || !std::isfinite(v)) {
                bad(("malformed " + head[c]).c_str());
            }
            return v;
        };
        Reading r{};
        const std::string &status = f[col[2]];
        r.echo = status != "timeout";
        if (r.echo && status != "ok" && status != "far" && status != "near") {
            bad("unknown status");
        }
        r.servo_deg = num(col[0]);
        r.range_m = r.echo ? num(col[1]) : 0.0;
        r.x = num(col[3]);
        r.y = num(col[4]);
        r.th = num(col[5]);
        rows.push_back(r);
    }
    return rows;
}

// One reading into the tree: the fan's endpoints at the range, inserted as one scan from
// the sonar (OctoMap lowers each cell a ray crossed once, raises each endpoint's once;
// an endpoint beyond max_range becomes a free ray of that length). Kept out of line: it
// is what callgrind counts (--toggle-collect=*insert_reading*), with the finish below.
__attribute__((noinline)) void insert_reading(octomap::OcTree &tree, const Options &o,
                                              const Reading &r, octomap::Pointcloud &fan)
{
    if (!r.echo && !o.timeout_free) {
        return;
    }
    if (r.echo && r.range_m < o.min_range_m) {
        return;
    }
    double c = std::cos(r.th);
    double s = std::sin(r.th);
    double sx = r.x + o.mount_x * c - o.mount_y * s - o.origin_x;
    double sy = r.y + o.mount_x * s + o.mount_y * c - o.origin_y;
    double z = 0.5 * o.cell_m;
    double bearing = r.th + (90.0 - r.servo_deg + o.mount_yaw_deg) * kPi / 180.0;
    // A timeout reaches past max_range: free rays all the way, no endpoint.
    double range = r.echo ? r.range_m : 2.0 * o.max_range_m;
    double reach = range < o.max_range_m ? range : o.max_range_m;
    double cone = o.cone_deg * kPi / 180.0;
    unsigned n = o.rays;
    if (n == 0) {
        n = (unsigned)std::ceil(reach * cone / o.cell_m) + 1u;
    }
    fan.clear();
    for (unsigned k = 0; k < n; k++) {
        double t = n > 1 ? bearing - 0.5 * cone + cone * k / (n - 1) : bearing;
        fan.push_back((float)(sx + range * std::cos(t)), (float)(sy + range * std::sin(t)),
                      (float)z);
    }
    tree.insertPointCloud(fan, octomap::point3d((float)sx, (float)sy, (float)z),
                          o.max_range_m, o.lazy, o.discretize);
}

// With lazy evaluation, the inner nodes' update that insertion left out: part of the
// cost of inserting, so counted with it.
__attribute__((noinline)) void insert_readings_finish(octomap::OcTree &tree, const Options &o)
{
    if (o.lazy) {
        tree.updateInnerOccupancy();
    }
}

int write_pgm(const Options &o, const octomap::OcTree &tree)
{
    std::vector<unsigned char> img((size_t)o.a * o.b);
    const unsigned zkey = kKeyCentre;
    for (unsigned b = 0; b < o.b; b++) {
        for (unsigned a = 0; a < o.a; a++) {
            octomap::OcTreeKey key((octomap::key_type)(kKeyCentre + a),
                                   (octomap::key_type)(kKeyCentre + b),
                                   (octomap::key_type)zkey);
            const octomap::OcTreeNode *node = tree.search(key);
            unsigned char v = node == nullptr ? kUnknown
                              : tree.isNodeOccupied(node) ? kOccupied : kFree;
            img[(size_t)(o.b - 1u - b) * o.a + a] = v;
        }
    }
    FILE *f = std::fopen(o.out, "wb");
    if (f == nullptr) {
        std::fprintf(stderr, "octomap_replay: cannot write %s: %s\n", o.out, std::strerror(errno));
        return 1;
    }
    std::fprintf(f, "P5\n%u %u\n255\n", o.a, o.b);
    std::fwrite(img.data(), 1, img.size(), f);
    if (std::ferror(f) || std::fclose(f) != 0) {
        std::fprintf(stderr, "octomap_replay: writing %s failed\n", o.out);
        return 1;
    }
    return 0;
}

} // namespace

int main(int argc, char **argv)
{
    Options o = parse(argc, argv);
    std::vector<Reading> rows = load(o);
    octomap::OcTree tree(o.cell_m);
    tree.setProbHit(o.prob_hit);
    tree.setProbMiss(o.prob_miss);
    tree.setClampingThresMin(o.clamp_min);
    tree.setClampingThresMax(o.clamp_max);
    octomap::Pointcloud fan;
    fan.reserve(1024);
    for (const Reading &r : rows) {
        insert_reading(tree, o, r, fan);
    }
    insert_readings_finish(tree, o);
    if (write_pgm(o, tree) != 0) {
        return 1;
    }
    std::printf("octomap_replay: %zu readings into %s (%zu tree nodes)\n", rows.size(), o.out,
                tree.size());
    return 0;
}
