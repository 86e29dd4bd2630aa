// facet-view's animation playback, with no window system in it: the time
// the scene is posed at, playing or paused, looped over the scene's time
// line (facet/animation.hpp). The viewer advances it each frame by the
// wall-clock time that passed; keys and the editor's slider move it.
#pragma once

#include <facet/animation.hpp>

#include <chrono>

namespace facet::view {

class Playback {
public:
    using Clock = std::chrono::steady_clock;

    // Starts at the time line's start, paused.
    void reset(const Timeline& timeline);
    // Takes a new time line (the scene file changed), keeping the time,
    // held within it, and whether it plays.
    void retime(const Timeline& timeline);
    double time() const { return time_; }
    bool playing() const { return playing_; }
    void set_playing(bool playing, Clock::time_point now = Clock::now());
    // Moves to `t`, held within the time line.
    void seek(double t);
    // Moves by `frames` frames of the time line's fps, from the frame at or
    // before the current time, and wraps.
    void step(int frames);
    // While playing: advances by the time since the last call (at most a
    // tenth of a second, so that a stall does not jump), wrapping at the
    // end. True if the time changed.
    bool advance(Clock::time_point now = Clock::now());
    const Timeline& timeline() const { return timeline_; }

private:
    double wrapped(double t) const;

    Timeline timeline_;
    double time_ = 0.0;
    bool playing_ = false;
    Clock::time_point last_{};
};

}  // namespace facet::view
