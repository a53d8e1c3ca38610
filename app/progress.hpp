// The live progress line of long commands: rewritten in place on a terminal, silent
// otherwise (logs and pipes get the final summary only).
#pragma once

#include <string>

namespace fird::app {

class ProgressLine {
  public:
    ProgressLine();
    ~ProgressLine(); // ends the line, if one was shown
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;
    bool live() const { return live_; }
    double elapsed_s() const;
    // Replaces the line with `text` (on a terminal only).
    void show(const std::string& text);
    // Ends the line (later output starts on a line of its own).
    void finish();

  private:
    bool live_ = false;
    bool shown_ = false;
    double start_s_ = 0.0;
};

// 83 -> "1:23", 4000 -> "1:06:40".
std::string clock_time(double seconds);

} // namespace fird::app
