#include "backend.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <chrono>
#include <cstring>
#include <system_error>
#include <thread>

extern char** environ;

namespace dawnforge::world {

namespace fs = std::filesystem;

std::vector<std::string> jobArguments(const BackendContext& ctx, const std::string& stage, int task, int cpus) {
    return {ctx.executable.string(), "world", "job", ctx.worldDir.string(), "--stage", stage,
            "--task", std::to_string(task), "--threads", std::to_string(cpus)};
}

fs::path jobLog(const fs::path& worldDir, const std::string& stage, int task) {
    return worldDir / "logs" / format("{}_{}.log", stage, task);
}

namespace {

// posix_spawn's file actions, destroyed however the scope is left.
class FileActions {
public:
    FileActions() { posix_spawn_file_actions_init(&actions_); }
    FileActions(const FileActions&) = delete;
    FileActions& operator=(const FileActions&) = delete;
    ~FileActions() { posix_spawn_file_actions_destroy(&actions_); }
    posix_spawn_file_actions_t* get() { return &actions_; }

private:
    posix_spawn_file_actions_t actions_;
};

// Starts one job with stdin from /dev/null and stdout and stderr in its log (truncated).
pid_t spawnJob(const BackendContext& ctx, const StageJobs& stage, int task) {
    const std::vector<std::string> args = jobArguments(ctx, stage.stage, task, stage.cpus);
    std::vector<char*> argv;
    for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);
    const std::string log = jobLog(ctx.worldDir, stage.stage, task).string();

    FileActions actions;
    posix_spawn_file_actions_addopen(actions.get(), STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(actions.get(), STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(actions.get(), STDOUT_FILENO, STDERR_FILENO);
    pid_t pid = 0;
    // glibc reports a failed exec or file action here (it spawns with CLONE_VFORK).
    const int error = posix_spawn(&pid, argv[0], actions.get(), nullptr, argv.data(), environ);
    if (error != 0)
        throw InputError(format("{}: cannot start the job {} {} (log {}): {}", args[0], stage.stage, task, log,
                                std::strerror(error)));
    return pid;
}

// Reaps the processes of `running` that ended and removes them; true if any did.
bool reapEnded(std::vector<pid_t>& running) {
    const auto ended = std::remove_if(running.begin(), running.end(), [](pid_t pid) {
        int status = 0;
        pid_t result;
        do result = ::waitpid(pid, &status, WNOHANG);
        while (result < 0 && errno == EINTR);
        return result == pid || (result < 0 && errno == ECHILD);  // ECHILD: reaped by someone else
    });
    const bool any = ended != running.end();
    running.erase(ended, running.end());
    return any;
}

// Calls ctx.poll() when a second has passed since the last call.
class PollTimer {
public:
    explicit PollTimer(const BackendContext& ctx) : ctx_(ctx) {}
    void tick() {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_ < std::chrono::seconds(1)) return;
        last_ = now;
        if (ctx_.poll) ctx_.poll();
    }

private:
    const BackendContext& ctx_;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

void runLocal(const std::vector<StageJobs>& stages, const BackendContext& ctx) {
    const fs::path logs = ctx.worldDir / "logs";
    std::error_code ec;
    fs::create_directories(logs, ec);
    if (ec) throw InputError(format("{}: cannot create the log folder: {}", logs.string(), ec.message()));

    const std::size_t workers = static_cast<std::size_t>(std::max(1, ctx.workers));
    PollTimer timer(ctx);
    // Stage by stage: a later stage's first task starts once the earlier stage's last one ended.
    for (const StageJobs& stage : stages) {
        // If starting a job or the progress throws, the jobs already started end with us.
        struct Running {
            std::vector<pid_t> pids;
            ~Running() {
                for (pid_t pid : pids) ::kill(pid, SIGTERM);
                for (pid_t pid : pids)
                    while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {}
            }
        } jobs;
        std::vector<pid_t>& running = jobs.pids;
        std::size_t next = 0;
        while (next < stage.tasks.size() || !running.empty()) {
            while (running.size() < workers && next < stage.tasks.size())
                running.push_back(spawnJob(ctx, stage, stage.tasks[next++]));
            // Short sleeps: a worker that frees up gets its next task within 50 ms.
            if (!reapEnded(running)) std::this_thread::sleep_for(std::chrono::milliseconds(50));
            timer.tick();
        }
    }
}

}  // namespace dawnforge::world
