#include "app/preview.h"
#include <nori/common.h>
#include <nori/film.h>
#include <nori/strutil.h>

#include <httplib.h>
#include <pthread.h>
#include <sys/socket.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <thread>

namespace nori {

extern const char *const kPreviewPage; // src/app/preview.html, embedded by CMake

namespace {

/// Host names that reach this machine's loopback, with or without a port.
bool isLoopbackHost(const std::string &host) {
    std::string name = host;
    if (!name.empty() && name.front() == '[') // [::1]:8080
        name = name.substr(0, name.find(']') + 1);
    else
        name = name.substr(0, name.find(':'));
    name = toLower(name);
    return name == "127.0.0.1" || name == "localhost" || name == "[::1]";
}

/// The name of the server's threads, by which serverCpuSeconds() finds them.
constexpr const char *kThreadName = "nori-preview";

/// Names the calling thread kThreadName (once per thread).
void nameThisThread() {
    thread_local bool named = false;
    if (!named) {
        pthread_setname_np(pthread_self(), kThreadName);
        named = true;
    }
}

/// One picture of a test: the PNG file's bytes, read when it is added.
struct Picture {
    std::string title;
    std::string png;
};

} // namespace

struct PreviewServer::State {
    httplib::Server server;
    std::thread thread;
    std::atomic<bool> listenReturned{false};
    int port = 0;
    std::string title;
    std::atomic<bool> *stop = nullptr;

    mutable std::mutex mutex;
    std::string kind = "render";
    std::string state = "loading";
    std::string message;
    uint64_t frame = 0;
    std::shared_ptr<const LayeredImage> image; ///< shared, so a request serialises outside the lock
    PassReport report;
    double timeBudget = 0.0;
    std::vector<Picture> pictures;
    // The cost of publishing passes (touched by the render's thread only).
    double developSeconds = 0.0;     ///< in all
    double lastDevelopSeconds = 0.0; ///< of the last pass published
    std::chrono::steady_clock::time_point lastPublish{};
    size_t passesPublished = 0, passesFinished = 0;
    /// Steady-clock time of the render's start, for the elapsed time shown before the
    /// first pass, and of the report's arrival: later, the time shown is the report's (which
    /// counts a resumed render's earlier time) plus the time since.
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point reportTime = start;

    std::string statusJSON() const;
    void serveImage(const httplib::Request &request, httplib::Response &response) const;
    void servePicture(const httplib::Request &request, httplib::Response &response) const;
};

std::string PreviewServer::State::statusJSON() const {
    std::lock_guard<std::mutex> lock(mutex);
    const bool running = state == "rendering" || state == "running";
    const auto now = std::chrono::steady_clock::now();
    double elapsed = report.seconds;
    if (running && report.samplesPerPixel > 0)
        elapsed += std::chrono::duration<double>(now - reportTime).count();
    else if (running)
        elapsed = std::chrono::duration<double>(now - start).count();
    // ETA from the rate of the passes so far (samples per pixel per second), capped by the
    // time budget; unknown before the first pass.
    double eta = -1.0;
    if (running && report.samplesPerPixel > 0) {
        const double secondsPerSpp = report.seconds / static_cast<double>(report.samplesPerPixel);
        eta = std::max(0.0,
                       secondsPerSpp * static_cast<double>(report.targetSamplesPerPixel) - elapsed);
        if (timeBudget > 0.0)
            eta = std::min(eta, std::max(0.0, timeBudget - elapsed));
    } else if (!running && state != "loading") {
        eta = 0.0;
    }
    std::string layers;
    if (image)
        for (const std::string &layer : image->layerNames())
            layers += fmt::format("{}{{\"name\":{},\"channels\":{}}}", layers.empty() ? "" : ",",
                                  jsonString(layer), image->channelsOf(layer).size());
    std::string pictureTitles;
    for (const Picture &picture : pictures)
        pictureTitles += (pictureTitles.empty() ? "" : ",") + jsonString(picture.title);
    return fmt::format(
        "{{\"kind\":{},\"title\":{},\"state\":{},\"message\":{},\"frame\":{},\"pass\":{},"
        "\"spp\":{},\"targetSpp\":{},\"elapsed\":{:.3f},\"eta\":{:.3f},\"width\":{},"
        "\"height\":{},\"layers\":[{}],\"pictures\":[{}]}}",
        jsonString(kind), jsonString(title), jsonString(state), jsonString(message), frame,
        report.pass, report.samplesPerPixel, report.targetSamplesPerPixel, elapsed, eta,
        image ? image->size().x() : 0, image ? image->size().y() : 0, layers, pictureTitles);
}

void PreviewServer::State::serveImage(const httplib::Request &request,
                                      httplib::Response &response) const {
    std::shared_ptr<const LayeredImage> current;
    uint64_t currentFrame = 0;
    {
        std::lock_guard<std::mutex> lock(mutex);
        current = image;
        currentFrame = frame;
    }
    const std::string layer = request.get_param_value("layer");
    if (!current || !current->hasLayer(layer)) {
        response.status = 404;
        response.set_content(current ? fmt::format("no layer '{}'", layer) : "no image yet",
                             "text/plain");
        return;
    }
    const std::vector<std::string> channels = current->channelsOf(layer);
    const Vector2i size = current->size();
    std::vector<float> values(static_cast<size_t>(size.prod()) * channels.size());
    for (size_t c = 0; c < channels.size(); ++c) {
        const std::string name = layer.empty() ? channels[c] : layer + "." + channels[c];
        const LayeredImage::Channel &channel = current->channels().at(name);
        for (int y = 0; y < size.y(); ++y)
            for (int x = 0; x < size.x(); ++x)
                values[(static_cast<size_t>(y) * size.x() + x) * channels.size() + c] =
                    channel(y, x);
    }
    response.set_header("X-Width", std::to_string(size.x()));
    response.set_header("X-Height", std::to_string(size.y()));
    response.set_header("X-Channels", std::to_string(channels.size()));
    response.set_header("X-Frame", std::to_string(currentFrame));
    response.set_header("Cache-Control", "no-store");
    response.set_content(reinterpret_cast<const char *>(values.data()),
                         values.size() * sizeof(float), "application/octet-stream");
}

void PreviewServer::State::servePicture(const httplib::Request &request,
                                        httplib::Response &response) const {
    std::lock_guard<std::mutex> lock(mutex);
    const std::string index = request.get_param_value("index");
    size_t k = 0;
    try {
        k = static_cast<size_t>(toInt(index, "index"));
    } catch (const NoriException &) {
        k = pictures.size();
    }
    if (k >= pictures.size()) {
        response.status = 404;
        response.set_content(fmt::format("no picture '{}'", index), "text/plain");
        return;
    }
    response.set_content(pictures[k].png, "image/png");
}

PreviewServer::PreviewServer(int port, std::string title, std::atomic<bool> *stop)
    : m_state(std::make_unique<State>()) {
    State &s = *m_state;
    s.title = std::move(title);
    s.stop = stop;
    // SO_REUSEADDR only: cpp-httplib's default adds SO_REUSEPORT, with which a second
    // nori would share a busy port with the first instead of being told it is busy.
    s.server.set_socket_options([](socket_t socket) {
        int yes = 1;
        setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    });
    // Few connections come (one page), so a small pool: the render keeps the cores.
    s.server.new_task_queue = [] { return new httplib::ThreadPool(4); };
    s.server.set_pre_routing_handler(
        [](const httplib::Request &request, httplib::Response &response) {
            nameThisThread();
            if (isLoopbackHost(request.get_header_value("Host")))
                return httplib::Server::HandlerResponse::Unhandled;
            response.status = 403;
            response.set_content("the preview answers requests to 127.0.0.1 or localhost only\n",
                                 "text/plain");
            return httplib::Server::HandlerResponse::Handled;
        });
    s.server.set_error_handler([](const httplib::Request &request, httplib::Response &response) {
        if (response.status == 404 && response.body.empty())
            response.set_content(fmt::format("not found: {} {}\n", request.method, request.path),
                                 "text/plain");
    });
    s.server.Get("/", [](const httplib::Request &, httplib::Response &response) {
        response.set_content(kPreviewPage, "text/html; charset=utf-8");
    });
    s.server.Get("/status", [&s](const httplib::Request &, httplib::Response &response) {
        response.set_header("Cache-Control", "no-store");
        response.set_content(s.statusJSON(), "application/json");
    });
    s.server.Get("/image", [&s](const httplib::Request &request, httplib::Response &response) {
        s.serveImage(request, response);
    });
    s.server.Get("/picture", [&s](const httplib::Request &request, httplib::Response &response) {
        s.servePicture(request, response);
    });
    s.server.Post("/stop", [&s](const httplib::Request &request, httplib::Response &response) {
        if (request.get_header_value("X-Nori-Action") != "stop") {
            response.status = 403;
            response.set_content("/stop needs the header X-Nori-Action: stop\n", "text/plain");
            return;
        }
        if (s.stop)
            s.stop->store(true);
        response.status = 204;
    });

    if (port < 0 || port > 65535)
        throw NoriException("--preview: port must lie in [0, 65535], got {}", port);
    if (port == 0)
        s.port = s.server.bind_to_any_port("127.0.0.1");
    else if (s.server.bind_to_port("127.0.0.1", port))
        s.port = port;
    if (s.port <= 0)
        throw NoriException("--preview: cannot serve on 127.0.0.1:{}: {} (is another nori or "
                            "server using it? give another port: --preview PORT)",
                            port, std::strerror(errno));
    s.thread = std::thread([&s] {
        nameThisThread();
        s.server.listen_after_bind();
        s.listenReturned = true;
    });
    // Server::stop() does nothing before the accept loop runs, so a server destroyed at
    // once would leave the loop running and its thread unjoinable: wait until it runs.
    while (!s.server.is_running() && !s.listenReturned)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

PreviewServer::~PreviewServer() {
    m_state->server.stop();
    if (m_state->thread.joinable())
        m_state->thread.join();
}

int PreviewServer::port() const {
    return m_state->port;
}

std::string PreviewServer::url() const {
    return fmt::format("http://127.0.0.1:{}/", m_state->port);
}

void PreviewServer::beginRender(size_t targetSpp, double timeBudget) {
    std::lock_guard<std::mutex> lock(m_state->mutex);
    m_state->kind = "render";
    m_state->state = "rendering";
    m_state->report = PassReport{};
    m_state->report.targetSamplesPerPixel = targetSpp;
    m_state->timeBudget = timeBudget;
    m_state->start = std::chrono::steady_clock::now();
}

void PreviewServer::passFinished(const Film &film, const PassReport &report) {
    State &s = *m_state;
    ++s.passesFinished;
    const auto start = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(start - s.lastPublish).count() < 100.0 * s.lastDevelopSeconds)
        return;
    publishPass(film.develop(), report);
    s.lastPublish = std::chrono::steady_clock::now();
    s.lastDevelopSeconds = std::chrono::duration<double>(s.lastPublish - start).count();
    s.developSeconds += s.lastDevelopSeconds;
    ++s.passesPublished;
}

std::string PreviewServer::costSummary(double seconds, int threads) const {
    const double cpuSeconds = seconds * threads, serverSeconds = serverCpuSeconds();
    return fmt::format("developing {} of {} passes took {:.0f} ms, the server used {:.0f} ms of "
                       "CPU: {:.2f}% of the render's {:.1f} CPU-seconds",
                       m_state->passesPublished, m_state->passesFinished,
                       m_state->developSeconds * 1e3, serverSeconds * 1e3,
                       100.0 * (m_state->developSeconds * threads + serverSeconds) /
                           std::max(cpuSeconds, 1e-9),
                       cpuSeconds);
}

void PreviewServer::publishPass(LayeredImage image, const PassReport &report) {
    auto shared = std::make_shared<const LayeredImage>(std::move(image));
    std::lock_guard<std::mutex> lock(m_state->mutex);
    m_state->image = std::move(shared);
    m_state->report = report;
    m_state->reportTime = std::chrono::steady_clock::now();
    ++m_state->frame;
}

void PreviewServer::finishRender(LayeredImage image, bool stopped, double seconds, size_t spp) {
    auto shared = std::make_shared<const LayeredImage>(std::move(image));
    std::lock_guard<std::mutex> lock(m_state->mutex);
    m_state->image = std::move(shared);
    m_state->report.seconds = seconds;
    m_state->report.samplesPerPixel = spp;
    m_state->state = stopped ? "stopped" : "done";
    ++m_state->frame;
}

void PreviewServer::beginTest() {
    std::lock_guard<std::mutex> lock(m_state->mutex);
    m_state->kind = "test";
    m_state->state = "running";
    m_state->start = std::chrono::steady_clock::now();
}

void PreviewServer::addPicture(const std::string &pngFile, const std::string &title) {
    std::ifstream file(pngFile, std::ios::binary);
    if (!file)
        throw NoriException("--preview: cannot read the picture '{}'", pngFile);
    Picture picture{title, std::string(std::istreambuf_iterator<char>(file), {})};
    std::lock_guard<std::mutex> lock(m_state->mutex);
    m_state->pictures.push_back(std::move(picture));
}

void PreviewServer::finishTest(bool passed) {
    std::lock_guard<std::mutex> lock(m_state->mutex);
    m_state->state = passed ? "passed" : "failed";
    m_state->report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - m_state->start).count();
}

void PreviewServer::fail(const std::string &message) {
    std::lock_guard<std::mutex> lock(m_state->mutex);
    m_state->state = "failed";
    m_state->message = message;
}

double PreviewServer::serverCpuSeconds() const {
    // /proc/self/task/<tid>/schedstat starts with the thread's time on a CPU in ns.
    double seconds = 0.0;
    std::error_code error;
    for (const auto &task : std::filesystem::directory_iterator("/proc/self/task", error)) {
        std::ifstream comm(task.path() / "comm"), schedstat(task.path() / "schedstat");
        std::string name;
        double nanoseconds = 0.0;
        if (std::getline(comm, name) && name == kThreadName && schedstat >> nanoseconds)
            seconds += nanoseconds * 1e-9;
    }
    return seconds;
}

void PreviewServer::waitForStop() const {
    // Polled rather than waited on with a condition variable: a signal handler (Ctrl-C)
    // sets the flag too, and may not notify one.
    while (!(m_state->stop && m_state->stop->load()))
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
}

} // namespace nori
