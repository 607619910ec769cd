// hadal-viewer's HTTP and WebSocket side (civetweb): serves the page (tools/viewer/web), three.js from
// Debian's libjs-three, the page's first state (/first.js, made by a callback: what the page shows at its
// load event), and one WebSocket endpoint (/ws) over which the push loop sends the state and the page sends
// its few commands (bag replay: play, pause, seek). Nothing else is served: no directory listing, no file
// outside the two roots.
//
// Access: with a token, every request must carry it, as ?token=T (the page's first request; it is then kept
// in a cookie, HttpOnly, SameSite=Strict) or that cookie. Without one (loopback only), a request must name
// a loopback host or the bound address in its Host header (no DNS rebinding). A WebSocket's Origin, when a
// browser sends one, must be the page's own (http://<Host>): another site open in the same browser cannot
// read the run.
#pragma once

#include <functional>
#include <memory>
#include <string>

namespace hadal::viewer {

struct WebOptions {
  std::string bind = "127.0.0.1";
  int port = 8080;          // 0: any free port (port() tells which)
  std::string token;        // empty: none required
  std::string web_root;     // index.html, viewer.js, viewer.css
  std::string three_root;   // libjs-three's /usr/share/javascript/three
};

// Called from civetweb's threads: when the page itself is requested (before its scripts), for the body of
// /first.js (the page's first state, part of its load: may block, briefly), when a page's WebSocket is open
// (with the query of its URL: "scene=ID" when the page has that scene already), and with each text message a
// page sends.
struct WebCallbacks {
  std::function<void()> on_page;
  std::function<std::string()> first_state;
  std::function<void(const void* client, const std::string& query)> on_client;
  std::function<void(const std::string& text)> on_command;
};

class WebServer {
 public:
  using ClientId = const void*;
  // Starts listening; null with the reason in *error (port taken, address not local, files missing).
  static std::unique_ptr<WebServer> start(const WebOptions& options, const WebCallbacks& callbacks,
                                          std::string* error);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  int port() const;

  // Sends to every admitted WebSocket, or to one open one (ignored when it has gone). binary: a binary
  // frame. A page is admitted to broadcasts once it has been sent everything (admit()), so that nothing
  // broadcast reaches it before what it builds on.
  void broadcast(const std::string& data, bool binary);
  void send(ClientId client, const std::string& data, bool binary);
  void admit(ClientId client);
  int clients() const;

  struct Impl;

 private:
  explicit WebServer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hadal::viewer
