#include "drone/ardrone2/h264_codec.hpp"

#include <cstring>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

namespace labo::ardrone2 {

namespace {

// Calls `fn(nal_type, start, end)` for each NAL unit; start includes the start code.
template <typename Fn>
void for_each_nal(std::span<const std::uint8_t> b, Fn fn) {
  auto start_code_at = [&](std::size_t i) -> std::size_t {
    if (i + 3 <= b.size() && b[i] == 0 && b[i + 1] == 0 && b[i + 2] == 1) return 3;
    if (i + 4 <= b.size() && b[i] == 0 && b[i + 1] == 0 && b[i + 2] == 0 && b[i + 3] == 1) return 4;
    return 0;
  };
  std::size_t i = 0;
  while (i < b.size() && start_code_at(i) == 0) ++i;
  while (i < b.size()) {
    const std::size_t sc = start_code_at(i);
    std::size_t j = i + sc;
    while (j < b.size() && start_code_at(j) == 0) ++j;
    if (i + sc < b.size()) fn(b[i + sc] & 0x1F, i, j);
    i = j;
  }
}

struct FrameDeleter {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct PacketDeleter {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
struct ContextDeleter {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct SwsDeleter {
  void operator()(SwsContext* s) const { sws_freeContext(s); }
};

// libav* print warnings about corrupt input on stderr; the link counts errors itself.
void quiet_libav() { av_log_set_level(AV_LOG_FATAL); }

}  // namespace

void find_parameter_sets(std::span<const std::uint8_t> annexb, std::uint8_t& sps_size, std::uint8_t& pps_size) {
  sps_size = pps_size = 0;
  for_each_nal(annexb, [&](int type, std::size_t s, std::size_t e) {
    const std::size_t n = std::min<std::size_t>(e - s, 255);
    if (type == 7 && sps_size == 0) sps_size = static_cast<std::uint8_t>(n);
    if (type == 8 && pps_size == 0) pps_size = static_cast<std::uint8_t>(n);
  });
}

bool contains_idr(std::span<const std::uint8_t> annexb) {
  bool idr = false;
  for_each_nal(annexb, [&](int type, std::size_t, std::size_t) { idr = idr || type == 5; });
  return idr;
}

// ---------------------------------------------------------------------------------------------------

struct H264Encoder::Impl {
  H264EncoderSettings settings;
  std::unique_ptr<AVCodecContext, ContextDeleter> ctx;
  std::unique_ptr<AVFrame, FrameDeleter> frame;
  std::unique_ptr<AVPacket, PacketDeleter> packet;
  std::unique_ptr<SwsContext, SwsDeleter> sws;
  cv::Mat resized;
  std::int64_t next_pts = 0;
  bool idr_requested = false;
  void open(const H264EncoderSettings& s);
};

// A libx264 encoder configured like the drone's stream; the first frame it encodes is an IDR.
void H264Encoder::Impl::open(const H264EncoderSettings& s) {
  if (s.width <= 0 || s.height <= 0 || s.width % 2 || s.height % 2)
    throw std::invalid_argument("H264Encoder: width and height must be positive and even");
  if (s.fps <= 0 || s.gop <= 0 || s.bitrate_kbps <= 0)
    throw std::invalid_argument("H264Encoder: fps, gop and bitrate must be positive");
  quiet_libav();
  settings = s;
  next_pts = 0;
  const AVCodec* codec = avcodec_find_encoder_by_name("libx264");
  if (!codec) throw std::runtime_error("H264Encoder: libavcodec was built without libx264");
  ctx.reset(avcodec_alloc_context3(codec));
  AVCodecContext* c = ctx.get();
  c->width = s.width;
  c->height = s.height;
  c->time_base = AVRational{1, s.fps};
  c->framerate = AVRational{s.fps, 1};
  c->pix_fmt = AV_PIX_FMT_YUV420P;
  c->gop_size = s.gop;
  c->keyint_min = s.gop;
  c->max_b_frames = 0;
  c->bit_rate = static_cast<std::int64_t>(s.bitrate_kbps) * 1000;
  // No AV_CODEC_FLAG_GLOBAL_HEADER: SPS/PPS go in band before every IDR, as on the drone.
  av_opt_set(c->priv_data, "profile", "baseline", 0);
  av_opt_set(c->priv_data, "preset", "ultrafast", 0);
  av_opt_set(c->priv_data, "tune", "zerolatency", 0);
  // Every keyframe an IDR (no open GOP), no scene-cut keyframes: IDR exactly every `gop` frames.
  // x264's fastest preset, but with the two tools a hardware baseline encoder like the drone's has and
  // ultrafast drops for speed: quarter-pel motion (subme 1; whole-pel copies shift a far panel's detail
  // by up to half a pixel per macroblock) and the in-loop deblocking filter (docs/ardrone2.md "The
  // simulated drone's encoder": an assumption, not verified on a drone). Test "link: the simulated
  // drone's encoder moves blocks by quarter pixels and deblocks".
  av_opt_set(c->priv_data, "x264-params", "scenecut=0:open-gop=0:repeat-headers=1:subme=1:deblock=1", 0);
  if (avcodec_open2(c, codec, nullptr) < 0) throw std::runtime_error("H264Encoder: cannot open libx264");
  frame.reset(av_frame_alloc());
  frame->format = c->pix_fmt;
  frame->width = s.width;
  frame->height = s.height;
  if (av_frame_get_buffer(frame.get(), 0) < 0) throw std::runtime_error("H264Encoder: no frame buffer");
  packet.reset(av_packet_alloc());
  sws.reset(sws_getContext(s.width, s.height, AV_PIX_FMT_BGR24, s.width, s.height, AV_PIX_FMT_YUV420P,
                                  SWS_BILINEAR, nullptr, nullptr, nullptr));
  if (!sws) throw std::runtime_error("H264Encoder: no swscale context");
}

H264Encoder::H264Encoder(const H264EncoderSettings& s) : impl_(std::make_unique<Impl>()) { impl_->open(s); }

H264Encoder::~H264Encoder() = default;
H264Encoder::H264Encoder(H264Encoder&&) noexcept = default;
H264Encoder& H264Encoder::operator=(H264Encoder&&) noexcept = default;
const H264EncoderSettings& H264Encoder::settings() const { return impl_->settings; }
void H264Encoder::request_idr() { impl_->idr_requested = true; }

void H264Encoder::set_bitrate_kbps(int kbps) {
  if (kbps <= 0) throw std::invalid_argument("H264Encoder: bitrate must be positive");
  if (kbps == impl_->settings.bitrate_kbps) return;
  // A new libx264 (its next frame an IDR, the GOP counted from there): libavcodec 59 ignores a bit_rate
  // set on an open context and keeps encoding at the old rate. Test "link: the H.264 encoder changes
  // its bit rate at run time".
  H264EncoderSettings s = impl_->settings;
  s.bitrate_kbps = kbps;
  impl_->open(s);
}

bool H264Encoder::encode(const cv::Mat& bgr, EncodedFrame& out) {
  if (bgr.empty() || bgr.type() != CV_8UC3) throw std::invalid_argument("H264Encoder: expected a CV_8UC3 image");
  Impl& m = *impl_;
  const cv::Mat* src = &bgr;
  if (bgr.cols != m.settings.width || bgr.rows != m.settings.height) {
    cv::resize(bgr, m.resized, cv::Size(m.settings.width, m.settings.height));
    src = &m.resized;
  }
  if (av_frame_make_writable(m.frame.get()) < 0) return false;
  const std::uint8_t* src_planes[1] = {src->data};
  const int src_stride[1] = {static_cast<int>(src->step[0])};
  sws_scale(m.sws.get(), src_planes, src_stride, 0, m.settings.height, m.frame->data, m.frame->linesize);
  m.frame->pts = m.next_pts++;
  // Force the IDR cadence ourselves so it never drifts from the PaVE frame numbering.
  const bool want_idr = m.frame->pts % m.settings.gop == 0 || m.idr_requested;
  m.idr_requested = false;
  m.frame->pict_type = want_idr ? AV_PICTURE_TYPE_I : AV_PICTURE_TYPE_NONE;
  m.frame->key_frame = want_idr ? 1 : 0;
  if (avcodec_send_frame(m.ctx.get(), m.frame.get()) < 0) return false;
  const int rc = avcodec_receive_packet(m.ctx.get(), m.packet.get());
  if (rc < 0) return false;
  out.data.assign(m.packet->data, m.packet->data + m.packet->size);
  out.keyframe = (m.packet->flags & AV_PKT_FLAG_KEY) != 0;
  out.index = m.frame->pts;
  find_parameter_sets(out.data, out.sps_size, out.pps_size);
  av_packet_unref(m.packet.get());
  return true;
}

// ---------------------------------------------------------------------------------------------------

std::string_view to_string(DecodeStatus status) {
  switch (status) {
    case DecodeStatus::Decoded: return "h264_decoded";
    case DecodeStatus::WaitingForIdr: return "h264_waiting_for_idr";
    case DecodeStatus::NoFrame: return "h264_no_frame";
    case DecodeStatus::Error: return "h264_decode_error";
  }
  return "h264_error";
}

struct H264Decoder::Impl {
  std::unique_ptr<AVCodecContext, ContextDeleter> ctx;
  std::unique_ptr<AVFrame, FrameDeleter> frame;
  std::unique_ptr<AVPacket, PacketDeleter> packet;
  SwsContext* sws = nullptr;  // sws_getCachedContext manages it
  std::vector<std::uint8_t> padded;
  bool seen_idr = false;
  int width = 0, height = 0;

  void open() {
    const AVCodec* codec = avcodec_find_decoder(AV_CODEC_ID_H264);
    if (!codec) throw std::runtime_error("H264Decoder: libavcodec has no H.264 decoder");
    ctx.reset(avcodec_alloc_context3(codec));
    ctx->flags |= AV_CODEC_FLAG_LOW_DELAY;
    ctx->thread_count = 1;  // frame threading would add latency
    if (avcodec_open2(ctx.get(), codec, nullptr) < 0) throw std::runtime_error("H264Decoder: cannot open");
  }
  ~Impl() { sws_freeContext(sws); }
};

H264Decoder::H264Decoder() : impl_(std::make_unique<Impl>()) {
  quiet_libav();
  impl_->open();
  impl_->frame.reset(av_frame_alloc());
  impl_->packet.reset(av_packet_alloc());
}

H264Decoder::~H264Decoder() = default;
H264Decoder::H264Decoder(H264Decoder&&) noexcept = default;
H264Decoder& H264Decoder::operator=(H264Decoder&&) noexcept = default;
int H264Decoder::width() const { return impl_->width; }
int H264Decoder::height() const { return impl_->height; }

void H264Decoder::reset() {
  impl_->seen_idr = false;
  avcodec_flush_buffers(impl_->ctx.get());
}

DecodeStatus H264Decoder::decode(std::span<const std::uint8_t> au, cv::Mat& bgr) {
  Impl& m = *impl_;
  if (!m.seen_idr) {
    if (!contains_idr(au)) return DecodeStatus::WaitingForIdr;
    m.seen_idr = true;
  }
  // libavcodec reads up to AV_INPUT_BUFFER_PADDING_SIZE past the end: copy into a padded buffer.
  m.padded.resize(au.size() + AV_INPUT_BUFFER_PADDING_SIZE);
  if (!au.empty()) std::memcpy(m.padded.data(), au.data(), au.size());
  std::memset(m.padded.data() + au.size(), 0, AV_INPUT_BUFFER_PADDING_SIZE);
  m.packet->data = m.padded.data();
  m.packet->size = static_cast<int>(au.size());
  const int sent = avcodec_send_packet(m.ctx.get(), m.packet.get());
  m.packet->data = nullptr;
  m.packet->size = 0;
  if (sent < 0 && sent != AVERROR(EAGAIN)) return DecodeStatus::Error;
  const int rc = avcodec_receive_frame(m.ctx.get(), m.frame.get());
  if (rc == AVERROR(EAGAIN)) return DecodeStatus::NoFrame;
  if (rc < 0) return DecodeStatus::Error;
  if (m.frame->decode_error_flags != 0) {
    av_frame_unref(m.frame.get());
    return DecodeStatus::Error;
  }
  const int w = m.frame->width, h = m.frame->height;
  if (w <= 0 || h <= 0) {
    av_frame_unref(m.frame.get());
    return DecodeStatus::Error;
  }
  m.sws = sws_getCachedContext(m.sws, w, h, static_cast<AVPixelFormat>(m.frame->format), w, h, AV_PIX_FMT_BGR24,
                               SWS_BILINEAR, nullptr, nullptr, nullptr);
  if (!m.sws) {
    av_frame_unref(m.frame.get());
    return DecodeStatus::Error;
  }
  bgr.create(h, w, CV_8UC3);
  std::uint8_t* dst[1] = {bgr.data};
  const int dst_stride[1] = {static_cast<int>(bgr.step[0])};
  sws_scale(m.sws, m.frame->data, m.frame->linesize, 0, h, dst, dst_stride);
  av_frame_unref(m.frame.get());
  m.width = w;
  m.height = h;
  return DecodeStatus::Decoded;
}

}  // namespace labo::ardrone2
