#include "localization/planar/h264_roundtrip.hpp"

#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/opt.h>
}

namespace labo {

namespace {

struct CodecContextDeleter {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct FrameDeleter {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct PacketDeleter {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
using CodecContext = std::unique_ptr<AVCodecContext, CodecContextDeleter>;
using Frame = std::unique_ptr<AVFrame, FrameDeleter>;
using Packet = std::unique_ptr<AVPacket, PacketDeleter>;

void check(int rc, const char* what) {
  if (rc < 0) throw std::runtime_error(std::string("h264 round trip: ") + what + " failed (" + std::to_string(rc) + ")");
}

void drain_decoder(AVCodecContext* dec, AVFrame* out, std::vector<cv::Mat>& decoded) {
  while (avcodec_receive_frame(dec, out) == 0) {
    cv::Mat y(out->height, out->width, CV_8UC1);
    for (int r = 0; r < out->height; ++r) std::memcpy(y.ptr(r), out->data[0] + r * out->linesize[0], static_cast<std::size_t>(out->width));
    decoded.push_back(y);
  }
}

void pump(AVCodecContext* enc, AVCodecContext* dec, AVPacket* pkt, AVFrame* out, std::vector<cv::Mat>& decoded) {
  while (avcodec_receive_packet(enc, pkt) == 0) {
    check(avcodec_send_packet(dec, pkt), "decoding");
    av_packet_unref(pkt);
    drain_decoder(dec, out, decoded);
  }
}

}  // namespace

std::vector<cv::Mat> h264_roundtrip(const std::vector<cv::Mat>& frames, double fps, int bitrate_bps) {
  if (frames.empty()) return {};
  const AVCodec* encoder = avcodec_find_encoder_by_name("libx264");
  if (!encoder) encoder = avcodec_find_encoder(AV_CODEC_ID_H264);
  const AVCodec* decoder = avcodec_find_decoder(AV_CODEC_ID_H264);
  if (!encoder || !decoder) throw std::runtime_error("h264 round trip: no H.264 encoder/decoder in this FFmpeg");
  CodecContext enc(avcodec_alloc_context3(encoder)), dec(avcodec_alloc_context3(decoder));
  enc->width = frames[0].cols;
  enc->height = frames[0].rows;
  enc->pix_fmt = AV_PIX_FMT_YUV420P;
  enc->time_base = AVRational{1, static_cast<int>(fps)};
  enc->framerate = AVRational{static_cast<int>(fps), 1};
  enc->gop_size = 15;
  enc->max_b_frames = 0;
  enc->bit_rate = bitrate_bps;
  av_opt_set(enc->priv_data, "profile", "baseline", 0);
  av_opt_set(enc->priv_data, "tune", "zerolatency", 0);
  av_opt_set(enc->priv_data, "preset", "veryfast", 0);
  check(avcodec_open2(enc.get(), encoder, nullptr), "opening the encoder");
  check(avcodec_open2(dec.get(), decoder, nullptr), "opening the decoder");
  Frame in(av_frame_alloc()), out(av_frame_alloc());
  Packet pkt(av_packet_alloc());
  in->format = AV_PIX_FMT_YUV420P;
  in->width = enc->width;
  in->height = enc->height;
  check(av_frame_get_buffer(in.get(), 0), "allocating a frame");
  std::vector<cv::Mat> decoded;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    check(av_frame_make_writable(in.get()), "making a frame writable");
    for (int r = 0; r < in->height; ++r) std::memcpy(in->data[0] + r * in->linesize[0], frames[i].ptr(r), static_cast<std::size_t>(in->width));
    for (int p = 1; p < 3; ++p) {
      for (int r = 0; r < in->height / 2; ++r) std::memset(in->data[p] + r * in->linesize[p], 128, static_cast<std::size_t>(in->width / 2));
    }
    in->pts = static_cast<int64_t>(i);
    check(avcodec_send_frame(enc.get(), in.get()), "encoding");
    pump(enc.get(), dec.get(), pkt.get(), out.get(), decoded);
  }
  check(avcodec_send_frame(enc.get(), nullptr), "flushing the encoder");
  pump(enc.get(), dec.get(), pkt.get(), out.get(), decoded);
  avcodec_send_packet(dec.get(), nullptr);
  drain_decoder(dec.get(), out.get(), decoded);
  if (decoded.size() != frames.size()) {
    throw std::runtime_error("h264 round trip: " + std::to_string(decoded.size()) + " frames decoded from " +
                             std::to_string(frames.size()));
  }
  return decoded;
}

}  // namespace labo
