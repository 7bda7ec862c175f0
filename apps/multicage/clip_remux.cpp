// The libav side of clip_io: probing clips, and remuxing the video OpenCV wrote with the
// source's audio tracks (stream copy, or decode, resample and re-encode).
#include "clip_remux.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdarg>
#include <cstdlib>
#include <memory>
#include <mutex>

#include "cli_util.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/audio_fifo.h>
#include <libswresample/swresample.h>
}

namespace fs = std::filesystem;

namespace multicage_cli {
namespace {

// ---- libav plumbing -----------------------------------------------------------------------

std::string avError(int code) {
    char text[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(code, text, sizeof(text));
    return text;
}

/** Throws a Failure "WHAT (libav's reason)" when a libav call returned an error. */
void check(int ret, const std::string& what) {
    if (ret < 0) throw Failure(what + " (" + avError(ret) + ")");
}

template <typename T>
T* allocated(T* p) {
    if (!p) throw std::bad_alloc();
    return p;
}

struct InputCloser {
    void operator()(AVFormatContext* c) const { avformat_close_input(&c); }
};
struct OutputCloser {
    void operator()(AVFormatContext* c) const {
        if (c->pb && !(c->oformat->flags & AVFMT_NOFILE)) avio_closep(&c->pb);
        avformat_free_context(c);
    }
};
struct PacketFree {
    void operator()(AVPacket* p) const { av_packet_free(&p); }
};
struct FrameFree {
    void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct CodecFree {
    void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct ResamplerFree {
    void operator()(SwrContext* s) const { swr_free(&s); }
};
struct FifoFree {
    void operator()(AVAudioFifo* f) const { av_audio_fifo_free(f); }
};
using Input = std::unique_ptr<AVFormatContext, InputCloser>;
using Output = std::unique_ptr<AVFormatContext, OutputCloser>;
using Packet = std::unique_ptr<AVPacket, PacketFree>;
using Frame = std::unique_ptr<AVFrame, FrameFree>;
using CodecContext = std::unique_ptr<AVCodecContext, CodecFree>;
using Resampler = std::unique_ptr<SwrContext, ResamplerFree>;
using SampleFifo = std::unique_ptr<AVAudioFifo, FifoFree>;

/** Opens path with libavformat and reads its stream information; empty (and error set) when it
cannot. */
Input openInput(const std::string& path, int& error) {
    AVFormatContext* raw = nullptr;
    error = avformat_open_input(&raw, path.c_str(), nullptr, nullptr);
    if (error < 0) return Input();
    Input in(raw);
    error = avformat_find_stream_info(in.get(), nullptr);
    return error < 0 ? Input() : std::move(in);
}

Input openInputOrThrow(const std::string& path) {
    int error = 0;
    Input in = openInput(path, error);
    if (!in) check(error, "cannot read " + path);
    return in;
}

/** The first stream of a type, as OpenCV's FFmpeg backend picks its video stream; -1 if none. */
int firstStream(const AVFormatContext* c, AVMediaType type) {
    for (unsigned i = 0; i < c->nb_streams; ++i)
        if (c->streams[i]->codecpar->codec_type == type) return static_cast<int>(i);
    return -1;
}

/** Where the video of a file starts (AV_TIME_BASE units): its frame 0 is the output's time 0,
and its audio keeps its offset from it. */
int64_t videoStart(const AVFormatContext* c) {
    const int v = firstStream(c, AVMEDIA_TYPE_VIDEO);
    if (v >= 0 && c->streams[v]->start_time != AV_NOPTS_VALUE)
        return av_rescale_q(c->streams[v]->start_time, c->streams[v]->time_base, AV_TIME_BASE_Q);
    return c->start_time != AV_NOPTS_VALUE ? c->start_time : 0;
}

// ---- remuxing: the video OpenCV wrote plus the source's audio tracks ---------------------

/** The packets of one output stream in decoding order, timestamps in its own time base. Each
feed reads its input on its own (other streams discarded), so feeds never share a demuxer. */
class Feed {
  public:
    virtual ~Feed() = default;
    /** The next packet, or false at the end. */
    virtual bool next(AVPacket* packet) = 0;
    AVStream* stream() const { return out_; }

  protected:
    /** Opens stream `index` of path, discarding the file's other streams. */
    void openSource(const std::string& path, int index) {
        path_ = path;
        in_ = openInputOrThrow(path);
        for (unsigned i = 0; i < in_->nb_streams; ++i)
            if (static_cast<int>(i) != index) in_->streams[i]->discard = AVDISCARD_ALL;
        source_ = in_->streams[index];
    }
    /** The next packet of the source stream; false at the end of the file. */
    bool readSource(AVPacket* packet) {
        for (;;) {
            const int ret = av_read_frame(in_.get(), packet);
            if (ret == AVERROR_EOF) return false;
            check(ret, "cannot read " + path_);
            if (packet->stream_index == source_->index) return true;
            av_packet_unref(packet);
        }
    }

    std::string path_;
    Input in_;
    AVStream* source_ = nullptr;
    AVStream* out_ = nullptr;
};

/** A stream copied packet by packet, shifted so that `start` (AV_TIME_BASE units, source time)
is 0, and cut at `end` (output time): packets wholly outside [0, end) are dropped. */
class CopyFeed : public Feed {
  public:
    CopyFeed(const std::string& path, int index, AVFormatContext* out, int64_t start, int64_t end)
        : start_(start), end_(end) {
        openSource(path, index);
        out_ = allocated(avformat_new_stream(out, nullptr));
        check(avcodec_parameters_copy(out_->codecpar, source_->codecpar),
              "cannot copy a stream of " + path);
        out_->codecpar->codec_tag = 0;         // the input container's tag; the muxer picks its own
        out_->time_base = source_->time_base;  // a hint: the muxer may choose another
        out_->disposition = source_->disposition;
        av_dict_copy(&out_->metadata, source_->metadata, 0);  // the language, mostly
    }

    bool next(AVPacket* packet) override {
        const AVRational tb = source_->time_base;
        const int64_t shift = av_rescale_q(start_, AV_TIME_BASE_Q, tb);
        while (readSource(packet)) {
            const int64_t ts = packet->pts != AV_NOPTS_VALUE ? packet->pts : packet->dts;
            if (ts != AV_NOPTS_VALUE) {
                const int64_t t = av_rescale_q(ts - shift, tb, AV_TIME_BASE_Q);
                const int64_t d = av_rescale_q(packet->duration, tb, AV_TIME_BASE_Q);
                if (t >= end_) {
                    av_packet_unref(packet);
                    return false;
                }
                if (d > 0 && t + d <= 0) {  // audio from before the video's first frame
                    av_packet_unref(packet);
                    continue;
                }
            }
            if (packet->pts != AV_NOPTS_VALUE) packet->pts -= shift;
            if (packet->dts != AV_NOPTS_VALUE) packet->dts -= shift;
            av_packet_rescale_ts(packet, tb, out_->time_base);
            packet->stream_index = out_->index;
            packet->pos = -1;
            return true;
        }
        return false;
    }

  private:
    int64_t start_, end_;
};

/** An audio stream decoded, converted (libswresample) and re-encoded to `codec`, with the same
shift and cut as CopyFeed but to the sample. */
class TranscodeFeed : public Feed {
  public:
    TranscodeFeed(const std::string& path, int index, AVFormatContext* out, AVCodecID codec,
                  int64_t start, int64_t end)
        : start_(start) {
        openSource(path, index);
        openDecoder();
        openEncoder(codec, out->oformat->flags & AVFMT_GLOBALHEADER);
        end_ = av_rescale_q(end, AV_TIME_BASE_Q, enc_->time_base);
        resampler_.reset(allocated(swr_alloc()));  // set up from the first decoded frame
        fifo_.reset(
            allocated(av_audio_fifo_alloc(enc_->sample_fmt, enc_->ch_layout.nb_channels, 1)));
        // The stream comes last: when the encoder cannot open, the output has no trace of it.
        out_ = allocated(avformat_new_stream(out, nullptr));
        check(avcodec_parameters_from_context(out_->codecpar, enc_.get()),
              "cannot set up the audio stream");
        out_->time_base = enc_->time_base;
        out_->disposition = source_->disposition;
        av_dict_copy(&out_->metadata, source_->metadata, 0);
    }

    bool next(AVPacket* packet) override {
        for (;;) {
            const int ret = avcodec_receive_packet(enc_.get(), packet);
            if (ret == 0) {
                av_packet_rescale_ts(packet, enc_->time_base, out_->time_base);
                packet->stream_index = out_->index;
                return true;
            }
            if (ret == AVERROR_EOF) return false;
            if (ret != AVERROR(EAGAIN)) check(ret, "cannot encode the audio");
            sendFrame();
        }
    }

  private:
    void openDecoder() {
        const AVCodec* codec = avcodec_find_decoder(source_->codecpar->codec_id);
        if (!codec) throw Failure("no decoder for its audio");
        dec_.reset(allocated(avcodec_alloc_context3(codec)));
        check(avcodec_parameters_to_context(dec_.get(), source_->codecpar),
              "cannot decode the audio of " + path_);
        dec_->pkt_timebase = source_->time_base;
        check(avcodec_open2(dec_.get(), codec, nullptr), "cannot decode the audio of " + path_);
    }

    void openEncoder(AVCodecID id, bool globalHeader) {
        const AVCodec* codec = avcodec_find_encoder(id);
        if (!codec) throw Failure(std::string("no ") + avcodec_get_name(id) + " encoder");
        enc_.reset(allocated(avcodec_alloc_context3(codec)));
        enc_->sample_rate = closestRate(codec, source_->codecpar->sample_rate);
        chooseLayout(codec, source_->codecpar->ch_layout);
        enc_->sample_fmt = codec->sample_fmts ? codec->sample_fmts[0] : AV_SAMPLE_FMT_FLTP;
        enc_->time_base = AVRational{1, enc_->sample_rate};
        if (globalHeader) enc_->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
        check(avcodec_open2(enc_.get(), codec, nullptr),
              std::string("cannot open the ") + codec->name + " encoder");
    }

    static int closestRate(const AVCodec* codec, int rate) {
        if (rate <= 0) rate = 48000;
        if (!codec->supported_samplerates) return rate;
        int best = codec->supported_samplerates[0];
        for (const int* r = codec->supported_samplerates; *r; ++r)
            if (std::abs(*r - rate) < std::abs(best - rate)) best = *r;
        return best;
    }

    /** The source's channel layout when the encoder takes it, else the default one for at most
    two channels (stereo or mono). */
    void chooseLayout(const AVCodec* codec, const AVChannelLayout& source) {
        const bool known = source.order != AV_CHANNEL_ORDER_UNSPEC && source.nb_channels > 0;
        bool taken = known && !codec->ch_layouts;
        for (const AVChannelLayout* l = codec->ch_layouts; known && l && l->nb_channels; ++l)
            taken = taken || av_channel_layout_compare(l, &source) == 0;
        if (taken)
            check(av_channel_layout_copy(&enc_->ch_layout, &source), "cannot copy a layout");
        else
            av_channel_layout_default(&enc_->ch_layout, std::clamp(source.nb_channels, 1, 2));
    }

    /** Gives the encoder its next frame from the FIFO, or the end of the stream. */
    void sendFrame() {
        const int size = enc_->frame_size > 0 ? enc_->frame_size : 1024;
        while (!inputDone_ && av_audio_fifo_size(fifo_.get()) < size) decodeMore();
        const int n = std::min(size, av_audio_fifo_size(fifo_.get()));
        if (n == 0) {
            check(avcodec_send_frame(enc_.get(), nullptr), "cannot encode the audio");
            return;
        }
        // A short last frame goes in as it is where the encoder takes one; else padded.
        const int caps = enc_->codec->capabilities;
        const bool shortOk =
            caps & (AV_CODEC_CAP_VARIABLE_FRAME_SIZE | AV_CODEC_CAP_SMALL_LAST_FRAME);
        const Frame frame(allocated(av_frame_alloc()));
        frame->nb_samples = shortOk ? n : size;
        frame->format = enc_->sample_fmt;
        frame->sample_rate = enc_->sample_rate;
        check(av_channel_layout_copy(&frame->ch_layout, &enc_->ch_layout), "cannot copy a layout");
        check(av_frame_get_buffer(frame.get(), 0), "cannot allocate audio samples");
        if (av_audio_fifo_read(fifo_.get(), reinterpret_cast<void**>(frame->extended_data), n) < n)
            throw Failure("cannot buffer the audio");
        if (frame->nb_samples > n)
            av_samples_set_silence(frame->extended_data, n, frame->nb_samples - n,
                                   enc_->ch_layout.nb_channels, enc_->sample_fmt);
        frame->pts = nextPts_;
        nextPts_ += frame->nb_samples;
        check(avcodec_send_frame(enc_.get(), frame.get()), "cannot encode the audio");
    }

    /** Decodes one more packet (at the end of the file: what the decoder and the resampler
    still hold) into the FIFO. */
    void decodeMore() {
        const Packet packet(allocated(av_packet_alloc()));
        if (readSource(packet.get())) {
            const int ret = avcodec_send_packet(dec_.get(), packet.get());
            // A damaged packet is skipped, as players do; other errors are real.
            if (ret != AVERROR_INVALIDDATA) check(ret, "cannot decode the audio of " + path_);
        } else {
            avcodec_send_packet(dec_.get(), nullptr);  // drain; AVERROR_EOF when drained already
        }
        const Frame decoded(allocated(av_frame_alloc()));
        int ret;
        while (!inputDone_ && (ret = avcodec_receive_frame(dec_.get(), decoded.get())) == 0) {
            queue(decoded.get());
            av_frame_unref(decoded.get());
        }
        if (inputDone_) return;
        if (ret == AVERROR_EOF) {
            queue(nullptr);  // flushes the resampler
            inputDone_ = true;
        } else if (ret != AVERROR(EAGAIN) && ret != AVERROR_INVALIDDATA) {
            check(ret, "cannot decode the audio of " + path_);
        }
    }

    /** Converts decoded samples to the encoder's format and queues the part inside [0, end). */
    void queue(AVFrame* decoded) {
        if (!decoded && !swr_is_initialized(resampler_.get())) return;
        if (decoded && decoded->ch_layout.order == AV_CHANNEL_ORDER_UNSPEC)
            av_channel_layout_default(&decoded->ch_layout, decoded->ch_layout.nb_channels);
        if (decoded && nextSample_ == AV_NOPTS_VALUE) {
            const int64_t ts = decoded->best_effort_timestamp;
            const int64_t shift = av_rescale_q(start_, AV_TIME_BASE_Q, source_->time_base);
            nextSample_ = ts == AV_NOPTS_VALUE
                              ? 0
                              : av_rescale_q(ts - shift, source_->time_base, enc_->time_base);
        }
        const Frame converted(allocated(av_frame_alloc()));
        converted->format = enc_->sample_fmt;
        converted->sample_rate = enc_->sample_rate;
        check(av_channel_layout_copy(&converted->ch_layout, &enc_->ch_layout),
              "cannot copy a layout");
        check(swr_convert_frame(resampler_.get(), converted.get(), decoded),
              "cannot convert the audio samples");
        const int64_t n = converted->nb_samples, t = nextSample_;
        nextSample_ += n;
        const int64_t from = std::clamp<int64_t>(-t, 0, n),
                      to = std::clamp<int64_t>(end_ - t, 0, n);
        if (t + n >= end_) inputDone_ = true;  // the video ends here: the rest is not needed
        if (to <= from) return;
        if (av_audio_fifo_size(fifo_.get()) == 0 && !queuedAny_) nextPts_ = t + from;
        queuedAny_ = true;
        // Plane pointers advanced past the samples before time 0.
        const int planes =
            av_sample_fmt_is_planar(enc_->sample_fmt) ? enc_->ch_layout.nb_channels : 1;
        const int bytes = av_get_bytes_per_sample(enc_->sample_fmt) *
                          (planes == 1 ? enc_->ch_layout.nb_channels : 1);
        std::vector<void*> data(planes);
        for (int p = 0; p < planes; ++p) data[p] = converted->extended_data[p] + from * bytes;
        if (av_audio_fifo_write(fifo_.get(), data.data(), static_cast<int>(to - from)) < to - from)
            throw Failure("cannot buffer the audio");
    }

    CodecContext dec_, enc_;
    Resampler resampler_;
    SampleFifo fifo_;
    int64_t start_, end_ = 0;              // end_: in samples of the output
    int64_t nextSample_ = AV_NOPTS_VALUE;  // output time of the next converted sample
    int64_t nextPts_ = 0;                  // output time of the next sample sent to the encoder
    bool queuedAny_ = false, inputDone_ = false;
};

/** Writes the feeds' packets in timestamp order, so that the muxer buffers little. */
void interleave(AVFormatContext* out, const std::vector<std::unique_ptr<Feed>>& feeds) {
    struct Head {
        Feed* feed;
        Packet packet;
        bool live;
    };
    std::vector<Head> heads;
    for (const auto& f : feeds) {
        Packet p(allocated(av_packet_alloc()));
        const bool live = f->next(p.get());
        heads.push_back(Head{f.get(), std::move(p), live});
    }
    const auto time = [](const Head& h) {
        return h.packet->dts != AV_NOPTS_VALUE   ? h.packet->dts
               : h.packet->pts != AV_NOPTS_VALUE ? h.packet->pts
                                                 : 0;
    };
    for (;;) {
        Head* first = nullptr;
        for (Head& h : heads)
            if (h.live &&
                (!first || av_compare_ts(time(h), h.feed->stream()->time_base, time(*first),
                                         first->feed->stream()->time_base) < 0))
                first = &h;
        if (!first) return;
        check(av_interleaved_write_frame(out, first->packet.get()), "cannot write a packet");
        first->live = first->feed->next(first->packet.get());
    }
}

}  // namespace

void silenceLibav() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (std::getenv("OPENCV_FFMPEG_DEBUG") || std::getenv("OPENCV_FFMPEG_LOGLEVEL")) return;
        av_log_set_callback([](void*, int, const char*, va_list) {});
    });
}

ClipProbe probeClip(const std::string& path) {
    checkInputFile(path);
    std::error_code ec;
    if (fs::file_size(path, ec) == 0 && !ec) throw Failure(path + ": the file is empty");
    int error = 0;
    const Input in = openInput(path, error);
    if (!in) throw Failure(path + ": not a video OpenCV's FFmpeg backend can read");
    ClipProbe p;
    p.videoStream = firstStream(in.get(), AVMEDIA_TYPE_VIDEO);
    if (p.videoStream >= 0) p.videoFrames = in->streams[p.videoStream]->nb_frames;
    for (unsigned i = 0; i < in->nb_streams; ++i)
        if (in->streams[i]->codecpar->codec_type == AVMEDIA_TYPE_AUDIO)
            p.audioStreams.push_back(static_cast<int>(i));
    return p;
}

std::vector<std::string> remuxWithAudio(const fs::path& video, const std::string& audioFrom,
                                        const std::vector<int>& audioStreams, const fs::path& to,
                                        int frames, double fps) {
    const int64_t duration = std::llround(frames * double(AV_TIME_BASE) / fps);
    AVFormatContext* raw = nullptr;
    check(avformat_alloc_output_context2(&raw, nullptr, nullptr, to.c_str()),
          "cannot start the file");
    const Output out(raw);
    const std::string ext = lowerExtension(to);

    std::vector<std::unique_ptr<Feed>> feeds;
    {
        const Input v = openInputOrThrow(video.string());
        const int index = firstStream(v.get(), AVMEDIA_TYPE_VIDEO);
        if (index < 0) throw Failure("the video encoder wrote no video stream");
        feeds.push_back(std::make_unique<CopyFeed>(video.string(), index, out.get(), 0, INT64_MAX));
    }
    std::vector<std::string> notes;
    if (!audioStreams.empty()) {
        const Input source = openInputOrThrow(audioFrom);
        const int64_t start = videoStart(source.get());
        const AVCodecID fallback = out->oformat->audio_codec;
        for (const int index : audioStreams) {
            const AVCodecID codec = source->streams[index]->codecpar->codec_id;
            const std::string what =
                std::string("the audio track (") + avcodec_get_name(codec) + ")";
            if (avformat_query_codec(out->oformat, codec, FF_COMPLIANCE_NORMAL) == 1) {
                feeds.push_back(
                    std::make_unique<CopyFeed>(audioFrom, index, out.get(), start, duration));
                continue;
            }
            try {
                feeds.push_back(std::make_unique<TranscodeFeed>(audioFrom, index, out.get(),
                                                                fallback, start, duration));
                notes.push_back(what + " re-encoded to " + avcodec_get_name(fallback) + ": " + ext +
                                " cannot hold it");
            } catch (const Failure& e) {
                notes.push_back(what + " cannot go into " + ext + ": left out (" + e.what() + ")");
            }
        }
    }

    if (!(out->oformat->flags & AVFMT_NOFILE))
        check(avio_open(&out->pb, to.c_str(), AVIO_FLAG_WRITE), "cannot open " + to.string());
    check(avformat_write_header(out.get(), nullptr), "cannot write the " + ext + " header");
    interleave(out.get(), feeds);
    check(av_write_trailer(out.get()), "cannot finish the " + ext + " file");
    return notes;
}

}  // namespace multicage_cli
