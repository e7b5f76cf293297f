#include "motorsim/outputs.h"

#include "motorsim/num_format.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace mcsim {
namespace {

namespace fs = std::filesystem;

std::string tmp_name(const std::string& path)
{
    const fs::path p(path);
    return (p.parent_path() / ("." + p.filename().string() + ".tmp")).string();
}

struct FileCloser {
    void operator()(std::FILE* f) const
    {
        if (f != nullptr) {
            std::fclose(f);
        }
    }
};

// Opens PATH.tmp, lets `body` write it, then renames it onto PATH.
template <typename Body>
void write_atomic(const std::string& path, Body body)
{
    const std::string tmp = tmp_name(path);
    std::unique_ptr<std::FILE, FileCloser> f(std::fopen(tmp.c_str(), "wb"));
    if (!f) {
        throw std::runtime_error(path + ": cannot create (" + std::strerror(errno) + ")");
    }
    body(f.get());
    const bool ok = std::ferror(f.get()) == 0;
    const int rc = std::fclose(f.release());
    if (!ok || rc != 0) {
        std::remove(tmp.c_str());
        throw std::runtime_error(path + ": write failed (" + std::strerror(errno) + ")");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        throw std::runtime_error(path + ": cannot rename into place (" + std::strerror(e) + ")");
    }
}

}  // namespace

// 10 significant digits (format_g10): below the float resolution of the
// telemetry and 1e-9 relative for the double plant values, at half the size
// of %.17g. Rows are formatted into a 1 MB block written with one fwrite.
void write_table_csv_atomic(const std::string& path, const char* const* names, int n_cols, const double* data,
                            std::size_t n_rows)
{
    write_atomic(path, [&](std::FILE* f) {
        constexpr std::size_t kBlock = 1 << 20;
        const std::size_t max_row = static_cast<std::size_t>(n_cols) * (kG10MaxChars + 1);
        std::vector<char> block(kBlock + max_row);
        char* const begin = block.data();
        char* p = begin;
        for (int c = 0; c < n_cols; ++c) {
            const std::size_t n = std::strlen(names[c]);
            std::memcpy(p, names[c], n);
            p += n;
            *p++ = c + 1 < n_cols ? ',' : '\n';
        }
        for (std::size_t k = 0; k < n_rows; ++k) {
            if (static_cast<std::size_t>(p - begin) > kBlock) {
                std::fwrite(begin, 1, static_cast<std::size_t>(p - begin), f);
                p = begin;
            }
            const double* r = data + k * static_cast<std::size_t>(n_cols);
            for (int c = 0; c < n_cols; ++c) {
                p = format_g10(p, r[c]);
                *p++ = ',';
            }
            p[-1] = '\n';
        }
        std::fwrite(begin, 1, static_cast<std::size_t>(p - begin), f);
    });
}

void write_csv_atomic(const std::string& path, const Row* rows, std::size_t n_rows)
{
    write_table_csv_atomic(path, kColumnNames, kNumColumns, n_rows > 0 ? rows[0].data() : nullptr, n_rows);
}

static void fmt_value(char* buf, std::size_t n, const MetricValue& v, bool json)
{
    if (const auto* i = std::get_if<std::int64_t>(&v)) {
        std::snprintf(buf, n, "%lld", static_cast<long long>(*i));
        return;
    }
    const double d = std::get<double>(v);
    if (!std::isfinite(d)) {
        std::snprintf(buf, n, "%s", json ? "null" : "nan");
        return;
    }
    std::snprintf(buf, n, "%.9g", d);
}

void write_metrics_json_atomic(const std::string& path, const MetricList& m)
{
    write_atomic(path, [&](std::FILE* f) {
        std::fputs("{\n", f);
        for (std::size_t k = 0; k < m.size(); ++k) {
            char buf[64];
            fmt_value(buf, sizeof(buf), m[k].second, true);
            std::fprintf(f, "  \"%s\": %s%s\n", m[k].first.c_str(), buf, k + 1 < m.size() ? "," : "");
        }
        std::fputs("}\n", f);
    });
}

void print_metrics(std::FILE* f, const MetricList& m)
{
    for (const auto& kv : m) {
        char buf[64];
        fmt_value(buf, sizeof(buf), kv.second, false);
        std::fprintf(f, "%s %s\n", kv.first.c_str(), buf);
    }
}

std::string run_plot(const std::string& python, const std::string& script, const std::string& csv,
                     const std::string& png)
{
    if (::access(python.c_str(), X_OK) != 0) {
        return "python not found at '" + python + "' (run scripts/setup.sh or set MC_PYTHON)";
    }
    if (::access(script.c_str(), R_OK) != 0) {
        return "plot script not found at '" + script + "'";
    }
    // Into a temporary name that still ends in .png (matplotlib picks the
    // format from the extension), then renamed like the other outputs.
    const fs::path p(png);
    const std::string tmp = (p.parent_path() / ("." + p.stem().string() + ".tmp.png")).string();
    std::vector<std::string> args = {python, script, csv, tmp};
    std::vector<char*> argv;
    for (std::string& a : args) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ);
    if (rc != 0) {
        return "cannot start '" + python + "': " + std::strerror(rc);
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) {
            return std::string("waitpid: ") + std::strerror(errno);
        }
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::remove(tmp.c_str());
        return script + " failed (exit status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")";
    }
    if (std::rename(tmp.c_str(), png.c_str()) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        return png + ": cannot rename into place (" + std::strerror(e) + ")";
    }
    return "";
}

}  // namespace mcsim
