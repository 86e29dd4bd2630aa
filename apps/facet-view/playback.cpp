#include "playback.hpp"

#include <algorithm>
#include <cmath>

namespace facet::view {

void Playback::reset(const Timeline& timeline) {
    timeline_ = timeline;
    time_ = timeline.start;
    playing_ = false;
}

void Playback::retime(const Timeline& timeline) {
    timeline_ = timeline;
    seek(time_);
    playing_ = playing_ && timeline.animated();
}

void Playback::set_playing(bool playing, Clock::time_point now) {
    playing_ = playing && timeline_.animated();
    last_ = now;
}

double Playback::wrapped(double t) const {
    if (!timeline_.animated()) return timeline_.start;
    const double length = timeline_.end - timeline_.start;
    const double into = std::fmod(t - timeline_.start, length);
    return timeline_.start + (into < 0.0 ? into + length : into);
}

void Playback::seek(double t) {
    time_ = timeline_.animated() ? std::clamp(t, timeline_.start, timeline_.end) : timeline_.start;
}

void Playback::step(int frames) {
    time_ = wrapped(timeline_.time_of(timeline_.frame_at(time_) + frames));
}

bool Playback::advance(Clock::time_point now) {
    if (!playing_) return false;
    const double seconds = std::min(0.1, std::chrono::duration<double>(now - last_).count());
    last_ = now;
    time_ = wrapped(time_ + seconds);
    return seconds > 0.0;
}

}  // namespace facet::view
