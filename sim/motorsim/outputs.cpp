#include "motorsim/outputs.h"

#include "motorsim/num_format.h"

#include <cerrno>
#include <csignal>
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

// The temporary files that exist right now, for the signal handler: fixed
// buffers (no allocation in the handler), unlink() is async-signal-safe.
constexpr int kMaxTemps = 2;
constexpr std::size_t kTempPathMax = 4096;
char g_temps[kMaxTemps][kTempPathMax];
volatile std::sig_atomic_t g_temp_used[kMaxTemps];

int temp_register(const std::string& path)
{
    for (int i = 0; i < kMaxTemps; ++i) {
        if (!g_temp_used[i] && path.size() < kTempPathMax) {
            std::memcpy(g_temps[i], path.c_str(), path.size() + 1);
            g_temp_used[i] = 1;
            return i;
        }
    }
    return -1;
}

void temp_release(int slot)
{
    if (slot >= 0) {
        g_temp_used[slot] = 0;
    }
}

extern "C" void remove_temps_and_die(int sig)
{
    for (int i = 0; i < kMaxTemps; ++i) {
        if (g_temp_used[i]) {
            ::unlink(g_temps[i]);
        }
    }
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

// Where writing PATH really goes: symlinks followed (relative targets
// against the link's directory), up to 40 levels like the kernel.
fs::path follow_links(const fs::path& path)
{
    fs::path p = path;
    for (int depth = 0; depth < 40; ++depth) {
        std::error_code ec;
        if (!fs::is_symlink(fs::symlink_status(p, ec))) {
            return p;
        }
        const fs::path t = fs::read_symlink(p, ec);
        if (ec) {
            return p;
        }
        p = t.is_absolute() ? t : p.parent_path() / t;
    }
    throw std::runtime_error(path.string() + ": too many levels of symbolic links");
}

// Writes an output like a careful Unix tool: "-" is stdout; a symlink is
// followed; a FIFO, a device or a socket is written in place (renaming over
// it would replace it); a regular file, or a new one, is written to a
// temporary file beside it and renamed onto it, so it appears whole or not
// at all. SIGINT/SIGTERM/SIGHUP while the temporary exists remove it
// (install_output_signal_handlers).
template <typename Body>
void write_atomic(const std::string& path, Body body)
{
    if (path == "-") {
        body(stdout);
        if (std::fflush(stdout) != 0 || std::ferror(stdout) != 0) {
            throw std::runtime_error("-: write to stdout failed (" + std::string(std::strerror(errno)) + ")");
        }
        return;
    }
    // What PATH is, as the kernel resolves it: that also follows the magic
    // links of /proc (/dev/stdout -> /proc/self/fd/1 -> "pipe:[N]"), whose
    // targets name no path that follow_links could walk to.
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (fs::exists(st) && !fs::is_regular_file(st)) {
        if (fs::is_directory(st)) {
            throw std::runtime_error(path + ": is a directory");
        }
        std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "wb"));
        if (!f) {
            throw std::runtime_error(path + ": cannot open (" + std::strerror(errno) + ")");
        }
        body(f.get());
        const bool ok = std::fflush(f.get()) == 0 && std::ferror(f.get()) == 0;
        const int e = errno;
        const int rc = std::fclose(f.release());
        if (!ok || rc != 0) {
            throw std::runtime_error(path + ": write failed (" + std::strerror(ok ? errno : e) + ")");
        }
        return;
    }
    // A regular file or a new one: the temporary goes beside the file the
    // links lead to, so the rename replaces that file and keeps the links.
    const fs::path target = follow_links(path);
    const std::string tmp = tmp_name(target.string());
    const int slot = temp_register(tmp);
    std::unique_ptr<std::FILE, FileCloser> f(std::fopen(tmp.c_str(), "wb"));
    if (!f) {
        temp_release(slot);
        throw std::runtime_error(path + ": cannot create (" + std::strerror(errno) + ")");
    }
    body(f.get());
    const bool ok = std::ferror(f.get()) == 0;
    const int rc = std::fclose(f.release());
    if (!ok || rc != 0) {
        std::remove(tmp.c_str());
        temp_release(slot);
        throw std::runtime_error(path + ": write failed (" + std::strerror(errno) + ")");
    }
    if (std::rename(tmp.c_str(), target.c_str()) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        temp_release(slot);
        throw std::runtime_error(path + ": cannot rename into place (" + std::strerror(e) + ")");
    }
    temp_release(slot);
}

}  // namespace

void install_output_signal_handlers()
{
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction sa {};
        sa.sa_handler = remove_temps_and_die;
        sigemptyset(&sa.sa_mask);
        sigaction(sig, &sa, nullptr);
    }
}

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
    const int slot = temp_register(tmp);
    struct Release {
        int slot;
        ~Release() { temp_release(slot); }
    } release{slot};
    std::vector<std::string> args = {python, script, csv, tmp};
    std::vector<char*> argv;
    argv.reserve(args.size() + 1);
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
