// The libav side of clip_io (private to the CLI): what libavformat sees in a clip, and the
// remux that puts the video OpenCV wrote together with the source's audio tracks.
#ifndef MULTICAGE_CLIP_REMUX_HPP
#define MULTICAGE_CLIP_REMUX_HPP

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace multicage_cli {

/** Mutes libav's own log (it prints e.g. "moov atom not found" straight to stderr; the Failures
say it in one line), once per process, unless OPENCV_FFMPEG_DEBUG or _LOGLEVEL is set. */
void silenceLibav();

/** What libavformat sees in a file. */
struct ClipProbe {
    int videoStream = -1;           // the first video stream (OpenCV decodes that one); -1 if none
    int64_t videoFrames = 0;        // the frame count its container states; 0: not stated
    std::vector<int> audioStreams;  // indices of its audio streams
};

/** Probes path. Throws ClipReader's Failures: "PATH: no such file" (and checkInputFile()'s
others), "PATH: the file is empty", "PATH: not a video OpenCV's FFmpeg backend can read". */
ClipProbe probeClip(const std::string& path);

/** Writes `to` (its extension picks the container): the video stream of `video` and the
audioStreams of audioFrom, cut at frames / fps seconds, audioFrom's first video frame at time 0.
Each track is stream-copied when the container takes its codec, else re-encoded to the
container's default audio codec, else left out. Returns the notes for the user on the audio
("the audio track (pcm_s16le) re-encoded to aac: .mp4 cannot hold it", "the audio track (X)
cannot go into .EXT: left out (WHY)"). Throws a Failure saying what failed, without naming `to`. */
std::vector<std::string> remuxWithAudio(const std::filesystem::path& video,
                                        const std::string& audioFrom,
                                        const std::vector<int>& audioStreams,
                                        const std::filesystem::path& to, int frames, double fps);

}  // namespace multicage_cli

#endif
