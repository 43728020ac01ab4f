#include "bench/common.hpp"

#include <algorithm>
#include <cassert>
#include <ctime>
#include <stdexcept>

namespace jetrace::bench {

double thread_cpu_ns() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e9 + static_cast<double>(ts.tv_nsec);
}

double cpu_timer_overhead_ns() {
    static const double overhead = [] {
        std::vector<double> v;
        for (int i = 0; i < 1001; ++i) v.push_back(CpuTimer().ns());
        return median(v);
    }();
    return overhead;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double median_ratio(const std::vector<double>& num, const std::vector<double>& den) {
    assert(num.size() == den.size());
    std::vector<double> r;
    r.reserve(num.size());
    for (std::size_t i = 0; i < num.size(); ++i) r.push_back(num[i] / den[i]);
    return median(std::move(r));
}

Vec3 fly(const PhysicsSettings& ps, double seconds) {
    CarState car;
    car.active = true;
    car.position = kFlightStart;
    car.velocity = kFlightVelocity;
    const Contacts none;
    const Input idle{};
    const auto steps = static_cast<int>(seconds * ps.tick_rate_hz + 0.5);
    for (int i = 0; i < steps; ++i) {
        const Vec3 v0 = car.velocity;
        apply_controls_and_forces(ps, none, idle, car);
        integrate(ps, v0, car);
    }
    return car.position;
}

Csv::Csv(const std::string& dir, const std::string& name, const std::vector<std::string>& header)
    : path_(dir + "/" + name) {
    f_ = std::fopen(path_.c_str(), "w");
    if (f_ == nullptr) throw std::runtime_error("cannot write " + path_);
    for (const std::string& h : header) cell(h);
    end();
}

Csv::~Csv() {
    if (f_ != nullptr) std::fclose(f_);
}

Csv& Csv::cell(const std::string& s) {
    std::fprintf(f_, "%s%s", first_ ? "" : ",", s.c_str());
    first_ = false;
    return *this;
}

Csv& Csv::cell(double v) {
    std::fprintf(f_, "%s%.9g", first_ ? "" : ",", v);
    first_ = false;
    return *this;
}

Csv& Csv::cell(long long v) {
    std::fprintf(f_, "%s%lld", first_ ? "" : ",", v);
    first_ = false;
    return *this;
}

void Csv::end() {
    std::fputc('\n', f_);
    first_ = true;
}

}  // namespace jetrace::bench
