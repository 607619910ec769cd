#include "web_server.h"

#include <civetweb.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

namespace hadal::viewer {

struct WebServer::Impl {
  WebOptions options;
  mg_context* context = nullptr;
  std::map<std::string, std::pair<std::string, std::string>> files;  // URI -> (path, MIME type)
  mutable std::mutex mutex;  // the client set, and every write to a WebSocket
  std::set<mg_connection*> clients;   // open
  std::set<mg_connection*> admitted;  // open and sent everything
  WebCallbacks callbacks;

  // Compares in time that depends on the lengths only (secret: the token, never empty).
  static bool same_secret(const std::string& secret, const char* given) {
    const std::size_t n = std::strlen(given);
    unsigned char diff = secret.size() == n ? 0 : 1;
    for (std::size_t i = 0; i < n; ++i) diff |= static_cast<unsigned char>(secret[i % secret.size()] ^ given[i]);
    return diff == 0;
  }

  // Whether the request may be served: it carries the token, or none is required and its Host is this
  // machine's loopback or the bound address.
  bool authorised(const mg_connection* conn) const {
    char value[256];
    if (!options.token.empty()) {
      const mg_request_info* info = mg_get_request_info(conn);
      if (info->query_string &&
          mg_get_var(info->query_string, std::strlen(info->query_string), "token", value, sizeof(value)) > 0 &&
          same_secret(options.token, value)) {
        return true;
      }
      const char* cookies = mg_get_header(conn, "Cookie");
      return cookies && mg_get_cookie(cookies, "hadal_token", value, sizeof(value)) > 0 &&
             same_secret(options.token, value);
    }
    const char* host = mg_get_header(conn, "Host");
    if (host == nullptr) return false;
    std::string name(host);
    name = name.substr(0, name.rfind(':') == std::string::npos ? name.size() : name.rfind(':'));
    return name == "localhost" || name.rfind("127.", 0) == 0 || name == options.bind;
  }

  // A WebSocket opened by a page of another origin (another site in the same browser) is refused.
  static bool same_origin(const mg_connection* conn) {
    const char* origin = mg_get_header(conn, "Origin");
    const char* host = mg_get_header(conn, "Host");
    return origin == nullptr || (host != nullptr && std::string(origin) == std::string("http://") + host);
  }

  static int serve(mg_connection* conn, void* data) {
    Impl& d = *static_cast<Impl*>(data);
    const mg_request_info* info = mg_get_request_info(conn);
    if (!d.authorised(conn)) {
      mg_send_http_error(conn, 403, "hadal-viewer: this viewer needs its token (?token=...)");
      return 403;
    }
    const std::string uri = info->local_uri;
    std::string text, mime;
    if (uri == "/first.js" && d.callbacks.first_state) {
      text = d.callbacks.first_state();
      mime = "text/javascript; charset=utf-8";
    } else {
      const auto file = d.files.find(uri);
      if (file == d.files.end()) {
        mg_send_http_error(conn, 404, "hadal-viewer: no %s here", info->local_uri);
        return 404;
      }
      if ((uri == "/" || uri == "/index.html") && d.callbacks.on_page) d.callbacks.on_page();
      std::ifstream in(file->second.first, std::ios::binary);
      std::ostringstream body;
      body << in.rdbuf();
      text = body.str();
      mime = file->second.second;
    }
    std::string cookie;
    if (!d.options.token.empty()) {
      cookie = "Set-Cookie: hadal_token=" + d.options.token + "; HttpOnly; SameSite=Strict\r\n";
    }
    mg_printf(conn,
              "HTTP/1.1 200 OK\r\nContent-Type: %s\r\nContent-Length: %zu\r\nCache-Control: no-store\r\n%s"
              "Connection: close\r\n\r\n",
              mime.c_str(), text.size(), cookie.c_str());
    mg_write(conn, text.data(), text.size());
    return 200;
  }

  static int ws_connect(const mg_connection* conn, void* data) {
    return static_cast<Impl*>(data)->authorised(conn) && same_origin(conn) ? 0 : 1;  // non-zero refuses
  }
  static void ws_ready(mg_connection* conn, void* data) {
    Impl& d = *static_cast<Impl*>(data);
    {
      std::lock_guard<std::mutex> lock(d.mutex);
      d.clients.insert(conn);
    }
    const char* query = mg_get_request_info(conn)->query_string;
    if (d.callbacks.on_client) d.callbacks.on_client(conn, query ? query : "");
  }
  static int ws_data(mg_connection* conn, int bits, char* text, size_t size, void* data) {
    Impl& d = *static_cast<Impl*>(data);
    const int opcode = bits & 0x0f;
    if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
    if (opcode == MG_WEBSOCKET_OPCODE_TEXT && d.callbacks.on_command) {
      d.callbacks.on_command(std::string(text, size));
    }
    (void)conn;
    return 1;
  }
  static void ws_close(const mg_connection* conn, void* data) {
    Impl& d = *static_cast<Impl*>(data);
    std::lock_guard<std::mutex> lock(d.mutex);
    d.clients.erase(const_cast<mg_connection*>(conn));
    d.admitted.erase(const_cast<mg_connection*>(conn));
  }

  void write_locked(mg_connection* conn, const std::string& data, bool binary) {
    if (mg_websocket_write(conn, binary ? MG_WEBSOCKET_OPCODE_BINARY : MG_WEBSOCKET_OPCODE_TEXT, data.data(),
                           data.size()) <= 0) {
      clients.erase(conn);  // gone; civetweb closes it
      admitted.erase(conn);
    }
  }
};

WebServer::WebServer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

WebServer::~WebServer() {
  if (impl_->context) mg_stop(impl_->context);
}

std::unique_ptr<WebServer> WebServer::start(const WebOptions& options, const WebCallbacks& callbacks,
                                            std::string* error) {
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->callbacks = callbacks;
  const std::string three_js = options.three_root + "/build/three.min.js";
  const std::string orbit_js = options.three_root + "/examples/js/controls/OrbitControls.js";
  impl->files = {{"/", {options.web_root + "/index.html", "text/html; charset=utf-8"}},
                 {"/index.html", {options.web_root + "/index.html", "text/html; charset=utf-8"}},
                 {"/viewer.js", {options.web_root + "/viewer.js", "text/javascript; charset=utf-8"}},
                 {"/viewer.css", {options.web_root + "/viewer.css", "text/css; charset=utf-8"}},
                 {"/three/three.min.js", {three_js, "text/javascript; charset=utf-8"}},
                 {"/three/OrbitControls.js", {orbit_js, "text/javascript; charset=utf-8"}}};
  for (const auto& [uri, file] : impl->files) {
    if (!std::filesystem::is_regular_file(file.first)) {
      *error = "missing " + file.first + (uri.rfind("/three/", 0) == 0 ? " (apt-get install libjs-three)" : "");
      return nullptr;
    }
  }
  mg_init_library(0);
  const std::string ports = options.bind + ":" + std::to_string(options.port);
  const char* civet_options[] = {"listening_ports", ports.c_str(), "num_threads", "16", "websocket_timeout_ms",
                                 "3600000", nullptr};
  mg_callbacks civet_callbacks{};
  impl->context = mg_start(&civet_callbacks, nullptr, civet_options);
  if (!impl->context) {
    *error = "cannot listen on " + ports + " (in use, or not an address of this machine)";
    return nullptr;
  }
  Impl* d = impl.get();
  for (const auto& [uri, file] : impl->files) mg_set_request_handler(d->context, (uri + "$").c_str(), &Impl::serve, d);
  mg_set_request_handler(d->context, "/first.js$", &Impl::serve, d);
  mg_set_websocket_handler(d->context, "/ws$", &Impl::ws_connect, &Impl::ws_ready, &Impl::ws_data, &Impl::ws_close, d);
  return std::unique_ptr<WebServer>(new WebServer(std::move(impl)));
}

int WebServer::port() const {
  mg_server_port ports[4];
  const int n = mg_get_server_ports(impl_->context, 4, ports);
  return n > 0 ? ports[0].port : -1;
}


void WebServer::broadcast(const std::string& data, bool binary) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  for (mg_connection* conn : std::set<mg_connection*>(impl_->admitted)) impl_->write_locked(conn, data, binary);
}

void WebServer::admit(ClientId client) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  auto* conn = static_cast<mg_connection*>(const_cast<void*>(client));
  if (impl_->clients.count(conn)) impl_->admitted.insert(conn);
}

void WebServer::send(ClientId client, const std::string& data, bool binary) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  auto* conn = static_cast<mg_connection*>(const_cast<void*>(client));
  if (impl_->clients.count(conn)) impl_->write_locked(conn, data, binary);
}

int WebServer::clients() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return static_cast<int>(impl_->clients.size());
}

}  // namespace hadal::viewer
