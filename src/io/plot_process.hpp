// The plotting child of a run: a Python process started when the run starts, which loads
// matplotlib (about half of its time) while the run computes, then waits to be told to draw
// the finished run's plots. The plots are thus drawn in less time after the run ends.
#pragma once

#include <sys/types.h>
#include <string>

namespace geodem {

class PlotProcess {
 public:
  PlotProcess() = default;  // no plots
  // Starts the plotting script on the run folder `dir` (it waits before reading anything).
  static PlotProcess start(const std::string& dir, bool quiet);
  // Tells it to draw and waits; false (with a warning on stderr unless quiet) when Python,
  // matplotlib or the script is missing, or the script failed.
  bool finish();
  // Without finish() (the run failed or was interrupted): tells it to leave without drawing.
  ~PlotProcess();
  PlotProcess(PlotProcess&& o) noexcept;
  PlotProcess& operator=(PlotProcess&& o) noexcept;
  PlotProcess(const PlotProcess&) = delete;
  PlotProcess& operator=(const PlotProcess&) = delete;

 private:
  void quit();
  pid_t pid_ = -1;
  int channel_ = -1;  // our end of the socket the child reads as its standard input
  std::string dir_;
  bool quiet_ = false;
  bool started_ = false;  // start() was called (even if the script was not found)
};

// Runs the plotting script on a finished run's folder (geodem plot DIR); false as finish().
bool make_plots(const std::string& dir, bool quiet);

}  // namespace geodem
