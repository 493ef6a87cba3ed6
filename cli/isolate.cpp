#include "cli/isolate.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string_view>

#include "core/error.hpp"
#include "core/files.hpp"

extern char** environ;

namespace gltf_pbr::cli {
namespace {

using Clock = std::chrono::steady_clock;

std::uint64_t resident_bytes(pid_t pid) {
  std::ifstream statm("/proc/" + std::to_string(pid) + "/statm");
  std::uint64_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
}

// The last non-empty line a child wrote to its standard error: its own account of what went wrong.
std::string last_line(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", seconds);
  return text;
}

// One decimal, more where the two figures would read alike ("30.04 MiB of memory, above 30 MiB",
// not "30.0 MiB of memory, above 30 MiB"); a whole limit as it was given.
std::string mib(std::uint64_t bytes, int decimals) {
  char text[40];
  std::snprintf(text, sizeof text, "%.*f MiB", decimals, static_cast<double>(bytes) / (1 << 20));
  return text;
}
std::string mib_above(std::uint64_t used, std::uint64_t limit) {
  int decimals = 1;
  while (decimals < 6 && mib(used, decimals) == mib(limit, decimals)) ++decimals;
  return mib(used, decimals) + " of memory, above " +
         (limit % (1 << 20) == 0 ? std::to_string(limit >> 20) + " MiB" : mib(limit, decimals));
}

constexpr char kParentVariable[] = "GLTF_PBR_ISOLATED_BY";

}  // namespace

void become_child_of_isolated_run() {
  const char* parent = std::getenv(kParentVariable);
  if (!parent) return;
  // Ended when the run that started it ends, however it ends: a hung child never outlives it.
  // SIGTERM, not SIGKILL: the child's signal thread (install_signal_cleanup) removes the
  // temporaries of a write in progress before it exits, where a kill left them in the output
  // folder of a run stopped with ^C.
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (std::to_string(::getppid()) != parent) std::_Exit(128 + SIGTERM);  // it ended before prctl
}

FileResult convert_in_child(const ConvertJob& job, const std::vector<std::string>& options, const ChildLimits& limits,
                            const std::filesystem::path& scratch, std::size_t index, nlohmann::json* child_cache) {
  const auto start = Clock::now();
  FileResult result;
  result.input = job.input.string();
  result.output = job.output.string();
  const auto finish = [&](std::string failure) {
    result.failure = std::move(failure);
    result.total_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return result;
  };
  const std::filesystem::path report = scratch / (std::to_string(index) + ".json");
  const std::filesystem::path errors = scratch / (std::to_string(index) + ".err");

  std::error_code error;
  // Options first and the input after "--", so a file named "-x.gltf" stays a file.
  std::vector<std::string> arguments{"gltf-pbr", "convert", "-q", "-j", "1", "--report", report.string()};
  if (job.output == job.input) {
    arguments.push_back("--in-place");
  } else {
    arguments.insert(arguments.end(), {"-o", job.output.string()});
  }
  // The child names a file's preview folder after the file, inside the folder it is given.
  if (!job.preview_dir.empty())
    arguments.insert(arguments.end(), {"--preview", job.preview_dir.parent_path().string()});
  arguments.insert(arguments.end(), options.begin(), options.end());
  arguments.insert(arguments.end(), {"--", job.input.string()});
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  // The child is told its parent, so it dies with it (become_child_of_isolated_run).
  std::vector<std::string> environment{std::string(kParentVariable) + "=" + std::to_string(::getpid())};
  for (char** variable = environ; *variable; ++variable)
    if (!std::string_view(*variable).starts_with(std::string(kParentVariable) + "="))
      environment.emplace_back(*variable);
  std::vector<char*> envp;
  for (std::string& variable : environment) envp.push_back(variable.data());
  envp.push_back(nullptr);

  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&files, STDERR_FILENO, errors.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  pid_t pid = 0;
  int spawned = 0;
  // Started through core's start_child: an interrupt of this run stops the child before the
  // scratch folder it writes its report into is removed. The pidfd also wakes the wait below the
  // moment the child ends; the 20 ms timeout samples its memory.
  struct Child {
    int pidfd = -1;
    ~Child() {
      if (pidfd < 0) return;
      forget_child(pidfd);
      ::close(pidfd);
    }
  } child;
  child.pidfd = start_child([&] {
    // /proc/self/exe, not the path it links to: a binary replaced during a long run still starts.
    spawned = ::posix_spawn(&pid, "/proc/self/exe", &files, nullptr, argv.data(), envp.data());
    return spawned == 0 ? static_cast<int>(::syscall(SYS_pidfd_open, pid, 0)) : -1;
  });
  posix_spawn_file_actions_destroy(&files);
  if (spawned != 0) return finish(std::string("cannot start a child process: ") + std::strerror(spawned));
  const int pidfd = child.pidfd;
  int status = 0;
  std::string stopped;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) return finish(std::string("lost the child process: ") + std::strerror(errno));
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (limits.seconds > 0 && seconds > limits.seconds)
      stopped = "took longer than " + seconds_text(limits.seconds) + " s (--file-timeout): stopped";
    else if (const std::uint64_t resident = limits.bytes ? resident_bytes(pid) : 0; resident > limits.bytes)
      stopped = "used " + mib_above(resident, limits.bytes) + " (--file-memory): stopped";
    if (!stopped.empty()) {
      ::kill(pid, SIGKILL);
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      break;
    }
    if (pidfd >= 0) {
      pollfd wait{pidfd, POLLIN, 0};
      ::poll(&wait, 1, 20);
    } else {
      ::usleep(20'000);
    }
  }
  const std::string said = last_line(errors);
  std::filesystem::remove(errors, error);
  if (!stopped.empty()) return finish(stopped);
  if (WIFSIGNALED(status))
    return finish("the child process converting it crashed: signal " + std::to_string(WTERMSIG(status)) + " (" +
                  ::strsignal(WTERMSIG(status)) + ")");
  const int code = WEXITSTATUS(status);
  if (code != 0 && code != 1)
    return finish("the child process converting it exited with code " + std::to_string(code) +
                  (said.empty() ? "" : ": " + said));
  try {
    const std::optional<Bytes> text = read_file(report);
    if (!text)
      return finish("the child process converting it exited with code " + std::to_string(code) + " and no report" +
                    (said.empty() ? "" : ": " + said));
    nlohmann::json written = nlohmann::json::parse(text->begin(), text->end());
    std::filesystem::remove(report, error);
    nlohmann::json& entry = written.at("files").at(0);
    result.status = file_status_from_name(entry.at("status").get<std::string>()).value_or(FileStatus::Failed);
    result.cached = entry.value("cached", false);
    if (child_cache && written.contains("cache")) *child_cache = written["cache"];
    std::string failure;
    if (result.status == FileStatus::Failed) {
      const nlohmann::json& what = entry.at("error");
      std::optional<std::uint64_t> offset;
      if (what.contains("offset") && what["offset"].is_number_unsigned()) offset = what["offset"].get<std::uint64_t>();
      const std::string where = InputError::where(what.value("pointer", ""), offset);
      failure = (where.empty() ? "" : where + ": ") + what.value("reason", "failed");
    }
    result.entry = std::move(entry);
    if (result.cached) result.entry->erase("cached");  // file_json marks it again
    return finish(failure);
  } catch (const nlohmann::json::exception& e) {
    return finish(std::string("the child process wrote a report this run cannot read: ") + e.what());
  }
}

}  // namespace gltf_pbr::cli
