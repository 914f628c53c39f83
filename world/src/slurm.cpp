// The Slurm backend: one job array per stage, submitted with sbatch, each depending on the
// one before with afterany, then squeue until none is left. shared/notes/world-scale.md,
// "Slurm on one node", has how to run a cluster here (tools/slurm-local up).
#include "backend.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <sstream>
#include <system_error>
#include <thread>

extern char** environ;

namespace dawnforge::world {

namespace fs = std::filesystem;

namespace {

struct Captured {
    int exitCode = 0;    // -1: the program could not be started (output says why)
    std::string output;  // stdout and stderr together
    int spawnError = 0;  // the errno when exitCode is -1 (ENOENT: not on PATH)
};

// Runs argv (argv[0] looked up on PATH, no shell) with stdin from /dev/null and returns its
// exit code (128 + the signal if one killed it) and its stdout and stderr.
Captured runCapture(const std::vector<std::string>& args) {
    std::vector<char*> argv;
    for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);

    int pipeFds[2];
    if (::pipe2(pipeFds, O_CLOEXEC) != 0) {
        const int error = errno;
        return {-1, format("cannot create a pipe: {}", std::strerror(error)), error};
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    // dup2 clears close-on-exec on the copies; both pipe ends themselves close at exec.
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDERR_FILENO);
    pid_t pid = 0;
    const int error = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipeFds[1]);
    if (error != 0) {
        ::close(pipeFds[0]);
        return {-1, format("cannot run {}: {}", args[0], std::strerror(error)), error};
    }

    Captured result;
    char buffer[4096];
    for (;;) {
        const ssize_t n = ::read(pipeFds[0], buffer, sizeof buffer);
        if (n > 0) result.output.append(buffer, static_cast<std::size_t>(n));
        else if (n == 0 || errno != EINTR) break;
    }
    ::close(pipeFds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return result;
}

std::string trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return std::string(s);
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> result;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        if (std::string t = trim(line); !t.empty()) result.push_back(std::move(t));
    return result;
}

// The line of a Slurm command's output that says best what went wrong, for a one-line
// message: munge's complaint, a fatal error, sbatch's summary, else the first error line.
// (The very first line is often a useless hint such as "If munged is up, restart with ...".)
std::string errorLine(const Captured& run) {
    const std::vector<std::string> all = lines(run.output);
    for (const char* sign : {"Munge encode failed", "fatal:", "submission failed", "error"})
        for (const std::string& line : all)
            if (line.find(sign) != std::string::npos) return line;
    return all.empty() ? format("exit code {}, no output", run.exitCode) : all.front();
}

// "0-3,7,9-12" from ascending task indices.
std::string arrayRanges(const std::vector<int>& tasks) {
    std::string ranges;
    for (std::size_t i = 0; i < tasks.size();) {
        std::size_t j = i;
        while (j + 1 < tasks.size() && tasks[j + 1] == tasks[j] + 1) ++j;
        if (!ranges.empty()) ranges += ',';
        ranges += j == i ? std::to_string(tasks[i]) : format("{}-{}", tasks[i], tasks[j]);
        i = j + 1;
    }
    return ranges;
}

// Slurm expands %-patterns in --output ("%a": the array index); "%%" is a plain "%".
std::string escapePercent(const std::string& path) {
    std::string escaped;
    for (char c : path) {
        escaped += c;
        if (c == '%') escaped += '%';
    }
    return escaped;
}

// The script every array task runs: the job's arguments come as the script's, its index from
// Slurm. Fixed, so that nothing from a folder's name is ever read by a shell. sbatch copies
// a script when it submits it, so it lives in the temp folder while the stages are submitted
// and the world folder holds the same files whichever backend built it.
struct TaskScript {
    fs::path path;
    explicit TaskScript(const fs::path& worldDir) : path(fs::temp_directory_path() / format("dawnforge-task-{}.sh", ::getpid())) {
        ensureOutputDirectory(worldDir / "logs");  // Slurm writes the logs there but does not create it
        writeFileAtomically(path, "#!/bin/sh\nexec \"$@\" --task \"$SLURM_ARRAY_TASK_ID\"\n");
    }
    ~TaskScript() {
        std::error_code ec;
        fs::remove(path, ec);
    }
};

// The sbatch command line of one stage's array: the job's arguments without its --task.
std::vector<std::string> sbatchArguments(const StageJobs& stage, const BackendContext& ctx, const fs::path& script,
                                         const std::string& previousJob) {
    const std::string dir = ctx.worldDir.string();
    std::vector<std::string> args = {"sbatch",
                                     "--parsable",
                                     "--array=" + arrayRanges(stage.tasks),
                                     "--job-name=dawnforge-" + stage.stage,
                                     format("--output={}/logs/{}_%a.log", escapePercent(dir), stage.stage),
                                     format("--cpus-per-task={}", stage.cpus),
                                     format("--mem={}M", stage.memoryMb)};
    if (!ctx.partition.empty()) args.push_back("--partition=" + ctx.partition);
    if (!previousJob.empty()) args.push_back("--dependency=afterany:" + previousJob);
    args.push_back("--chdir=" + dir);
    args.push_back(script.string());
    std::vector<std::string> job = jobArguments(ctx, stage.stage, 0, stage.cpus);
    const auto task = std::find(job.begin(), job.end(), "--task");
    DAWNFORGE_ASSERT(task != job.end() && task + 1 != job.end(), "jobArguments has no --task");
    job.erase(task, task + 2);
    args.insert(args.end(), job.begin(), job.end());
    return args;
}

// The job id that `sbatch --parsable` printed ("ID" or "ID;cluster"), or "" if none.
std::string parsedJobId(const std::string& output) {
    for (const std::string& line : lines(output)) {
        const std::string id = line.substr(0, line.find(';'));
        if (!id.empty() && std::all_of(id.begin(), id.end(), [](unsigned char c) { return std::isdigit(c); }))
            return id;
    }
    return "";
}

bool controllerUnreachable(const std::string& output) {
    for (const char* sign : {"Unable to contact slurm controller", "Unable to establish", "Connection refused",
                             "Zero Bytes were transmitted", "Munge", "munge", "auth_g_", "slurm.conf",
                             "authentication", "Socket timed out", "configuration source"})
        if (output.find(sign) != std::string::npos) return true;
    return false;
}

// Submits one stage's array and returns its job id; throws InputError with one line.
std::string submitStage(const StageJobs& stage, const BackendContext& ctx, const fs::path& script,
                        const std::string& previousJob) {
    const Captured run = runCapture(sbatchArguments(stage, ctx, script, previousJob));
    if (run.spawnError == ENOENT)
        throw InputError("--backend slurm: sbatch is not on PATH: install Slurm's commands (Debian: slurm-client) "
                         "or build where a cluster is");
    if (run.exitCode == -1) throw InputError(format("--backend slurm: {}", run.output));
    if (run.exitCode != 0) {
        if (controllerUnreachable(run.output))
            throw InputError(format("--backend slurm: no Slurm controller answers ({}): "
                                    "start one (tools/slurm-local up) or check slurm.conf",
                                    errorLine(run)));
        // Indices at or above slurm.conf's MaxArraySize (default 1001) give this error.
        const std::string hint = run.output.find("job array") == std::string::npos
                                     ? ""
                                     : format(": task {} needs MaxArraySize > {} in slurm.conf", stage.tasks.back(),
                                              stage.tasks.back());
        throw InputError(format("--backend slurm: sbatch refused the {} stage's {} task(s) ({}){}", stage.stage,
                                stage.tasks.size(), errorLine(run), hint));
    }
    std::string id = parsedJobId(run.output);
    if (id.empty())
        throw InputError(format("--backend slurm: sbatch printed no job id for the {} stage ({})", stage.stage,
                                errorLine(run)));
    return id;
}

// Cancels what was submitted before a later submission failed (best effort: the error that
// follows says what went wrong).
void cancelSubmitted(const std::vector<std::string>& jobIds) {
    if (jobIds.empty()) return;
    std::vector<std::string> args = {"scancel"};
    args.insert(args.end(), jobIds.begin(), jobIds.end());
    runCapture(args);
}

std::string joined(const std::vector<std::string>& items, char separator) {
    std::string result;
    for (const std::string& item : items) {
        if (!result.empty()) result += separator;
        result += item;
    }
    return result;
}

// Whether any of the jobs is still queued, running or completing. A job that left the queue
// makes squeue fail with "Invalid job id specified" when it is the only one named.
bool anyQueued(const std::vector<std::string>& jobIds, std::string& failure) {
    const Captured run = runCapture({"squeue", "-h", "-j", joined(jobIds, ','), "-o", "%i"});
    failure.clear();
    if (run.exitCode == 0) {
        for (const std::string& line : lines(run.output))
            if (std::isdigit(static_cast<unsigned char>(line.front()))) return true;
        return false;
    }
    if (run.output.find("Invalid job id") != std::string::npos) return false;
    failure = errorLine(run);
    return true;
}

}  // namespace

void runSlurm(const std::vector<StageJobs>& stages, const BackendContext& ctx) {
    if (ctx.worldDir.string().find('\\') != std::string::npos)
        throw InputError(format("--backend slurm: {}: a world folder whose path holds a backslash cannot hold "
                                "Slurm's logs (Slurm then ignores %a in --output): rename it",
                                ctx.worldDir.string()));
    std::vector<std::string> jobIds;
    {
        const TaskScript script(ctx.worldDir);
        for (const StageJobs& stage : stages) {
            if (stage.tasks.empty()) continue;
            try {
                jobIds.push_back(submitStage(stage, ctx, script.path, jobIds.empty() ? "" : jobIds.back()));
            } catch (const InputError&) {
                cancelSubmitted(jobIds);
                throw;
            }
        }
    }

    // squeue once a second until none is left. A controller that stops answering for a minute
    // (stopped, or restarted without its state) leaves us no way to know when the jobs end.
    constexpr auto giveUpAfter = std::chrono::seconds(60);
    auto lastAnswer = std::chrono::steady_clock::now();
    std::string failure;
    while (!jobIds.empty() && anyQueued(jobIds, failure)) {
        const auto now = std::chrono::steady_clock::now();
        if (failure.empty()) lastAnswer = now;
        else if (now - lastAnswer > giveUpAfter)
            throw InputError(format("--backend slurm: squeue has failed for a minute ({}); the jobs {} may still "
                                    "run: check with squeue, then build again",
                                    failure, joined(jobIds, ',')));
        if (ctx.poll) ctx.poll();
        std::this_thread::sleep_for(std::chrono::seconds(1));
    }
    if (ctx.poll) ctx.poll();
}

}  // namespace dawnforge::world
