// The live preview of `nori --preview`: an HTTP server on 127.0.0.1 that serves one page
// (src/app/preview.html) showing a render as its passes finish, or the χ² pictures
// of a test file as they are drawn, and the data that page fetches. Nothing else.
#pragma once

#include <nori/layeredimage.h>
#include <nori/render.h>

#include <atomic>
#include <memory>
#include <string>

namespace nori {

/// Where the preview serves unless told otherwise.
constexpr int kDefaultPreviewPort = 8080;

/// The server's routes, for the page and for scripts:
///   GET  /                 the page (text/html)
///   GET  /status           JSON: kind ("render" or "test"), title, state ("loading",
///                          "rendering", "done", "stopped"; for a test "running",
///                          "passed", "failed"; "failed" with a message on an error), message,
///                          frame (counts published images), pass, spp, targetSpp,
///                          elapsed, eta (seconds; -1 unknown), width, height, layers
///                          ([{name, channels}], "" is the beauty), pictures ([titles])
///   GET  /image?layer=L    the latest image's layer L as little-endian float32,
///                          row-major from the top row, channels interleaved; headers
///                          X-Width, X-Height, X-Channels and X-Frame describe it
///   GET  /picture?index=K  the K-th χ² picture of a test (image/png)
///   POST /stop             with the header "X-Nori-Action: stop": ends the render as
///                          Ctrl-C does (or, once it has ended, ends `--preview-wait`)
/// Any other path or method is a 404. A request whose Host is not a loopback name
/// (127.0.0.1, localhost, [::1]) is refused with 403, so that a web page elsewhere cannot
/// reach the server through DNS rebinding; the custom header of /stop makes a browser ask
/// before sending it from another origin (a CORS preflight, which gets a 404).
class Film;

class PreviewServer {
public:
    /// Serves on 127.0.0.1:port (0: any free port) from a thread of its own. `stop` is the
    /// flag that /stop sets. Throws a NoriException naming the port when it is taken.
    PreviewServer(int port, std::string title, std::atomic<bool> *stop);
    ~PreviewServer();
    PreviewServer(const PreviewServer &) = delete;
    PreviewServer &operator=(const PreviewServer &) = delete;

    int port() const;
    std::string url() const;

    /// A render of `targetSpp` samples per pixel starts (timeBudget in seconds, 0: none).
    void beginRender(size_t targetSpp, double timeBudget);
    /// A pass has finished: the film is developed and replaces the last image, unless the
    /// last develop took more than 1% of the time since the last publish. Every worker
    /// waits while a pass is developed, so this keeps the wait within 1% of the render
    /// however short its passes are (the last pass still reaches the page: finishRender).
    void passFinished(const Film &film, const PassReport &report);
    /// Publishes `image` as the latest pass's (what passFinished does after developing).
    void publishPass(LayeredImage image, const PassReport &report);
    /// What being watched cost a render of `seconds` on `threads` workers: the develop
    /// waits and the server threads' CPU time, as one line for the end of the render.
    std::string costSummary(double seconds, int threads) const;
    /// The render has ended; `image` is its final image (with any layers added since, such
    /// as the denoised one). `stopped`: cancelled by /stop or Ctrl-C.
    void finishRender(LayeredImage image, bool stopped, double seconds, size_t spp);

    /// A test file starts running; its χ² pictures are added as they are written.
    void beginTest();
    void addPicture(const std::string &pngFile, const std::string &title);
    void finishTest(bool passed);

    /// Something went wrong before or during the render (the page shows `message`).
    void fail(const std::string &message);

    /// CPU time the server's threads (the HTTP pool and its listener) have used so far:
    /// the render's cost of being watched, besides developing the passes (Linux's
    /// /proc/self/task/*/schedstat; 0 where that is missing).
    double serverCpuSeconds() const;

    /// Blocks until the stop flag is set (by /stop or by the caller's Ctrl-C handler).
    void waitForStop() const;

private:
    struct State;
    std::unique_ptr<State> m_state;
};

} // namespace nori
