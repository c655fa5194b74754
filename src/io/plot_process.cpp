#include "io/plot_process.hpp"

#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <utility>

#ifndef GEODEM_PYTHON_DIR
#define GEODEM_PYTHON_DIR "python"
#endif

extern char** environ;

namespace geodem {

namespace {

std::string python_command() {
  const char* env = std::getenv("GEODEM_PYTHON");
  if (env) return env;
  return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

void warn_failed(const std::string& dir) {
  std::fprintf(stderr,
               "warning: plotting failed (is python3-matplotlib installed?); the CSV, JSON "
               "and VTK outputs are complete; run 'geodem plot %s' later\n",
               dir.c_str());
}

}  // namespace

PlotProcess PlotProcess::start(const std::string& dir, bool quiet) {
  PlotProcess p;
  p.dir_ = dir;
  p.quiet_ = quiet;
  p.started_ = true;
  const std::string script = std::string(GEODEM_PYTHON_DIR) + "/geodem_plot.py";
  if (!std::filesystem::exists(script)) return p;
  // A socket rather than a pipe: a write to a child that died raises no SIGPIPE with
  // MSG_NOSIGNAL. Our end is closed on exec in any other child.
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) return p;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 0);  // dup2 clears close-on-exec
  const std::string python = python_command();
  std::string a0 = python, a1 = script, a2 = "--wait", a3 = dir;
  char* argv[] = {a0.data(), a1.data(), a2.data(), a3.data(), nullptr};
  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, python.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  if (rc != 0) {
    ::close(fds[0]);
    return p;
  }
  p.pid_ = pid;
  p.channel_ = fds[0];
  return p;
}

bool PlotProcess::finish() {
  if (!started_) return false;
  started_ = false;
  const std::string script = std::string(GEODEM_PYTHON_DIR) + "/geodem_plot.py";
  if (pid_ < 0) {
    if (!quiet_) {
      if (!std::filesystem::exists(script))
        std::fprintf(stderr, "warning: plotting script %s not found; no PNG plots\n",
                     script.c_str());
      else
        warn_failed(dir_);
    }
    return false;
  }
  static const char go[] = "go\n";
  const bool told = ::send(channel_, go, sizeof go - 1, MSG_NOSIGNAL) == sizeof go - 1;
  ::close(channel_);
  channel_ = -1;
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  const bool ok = told && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!ok && !quiet_) warn_failed(dir_);
  return ok;
}

void PlotProcess::quit() {
  if (channel_ >= 0) ::close(channel_);  // the child reads the end of its input and leaves
  channel_ = -1;
  if (pid_ >= 0) {
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
  pid_ = -1;
  started_ = false;
}

PlotProcess::~PlotProcess() {
  quit();
}

PlotProcess::PlotProcess(PlotProcess&& o) noexcept
    : pid_(std::exchange(o.pid_, -1)),
      channel_(std::exchange(o.channel_, -1)),
      dir_(std::move(o.dir_)),
      quiet_(o.quiet_),
      started_(std::exchange(o.started_, false)) {}

PlotProcess& PlotProcess::operator=(PlotProcess&& o) noexcept {
  if (this != &o) {
    quit();
    pid_ = std::exchange(o.pid_, -1);
    channel_ = std::exchange(o.channel_, -1);
    dir_ = std::move(o.dir_);
    quiet_ = o.quiet_;
    started_ = std::exchange(o.started_, false);
  }
  return *this;
}

bool make_plots(const std::string& dir, bool quiet) {
  return PlotProcess::start(dir, quiet).finish();
}

}  // namespace geodem
