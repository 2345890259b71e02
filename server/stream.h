// Server-Sent Events for POST /plan and POST /solve with "stream": true (contract section 9).
//
// The stream's events, in order:
//   event: stage     {"stage": "translating"|"repairing"|"solving", "elapsed_ms", "llm_call"?}
//   event: solution  {"objective", "kind", "cost", "makespan", "horizon", "elapsed_ms"}, one per
//                    improving verified plan
//   event: item      POST /eval: one item's line as it ends (contract section 15)
//   event: done      the whole answer, exactly what the route answers without streaming
// or, instead of done, a last
//   event: error     {"status": <the HTTP status the route would answer>, "error": {...}}, the
//                    error without "request_id" (the response head's X-Request-Id names it)
// The response is 200 text/event-stream once streaming was asked for and a solver place could be
// reserved for it (`reserve`); a server whose places are all taken answers 503 busy with
// Retry-After instead, before any head is sent. A request that turns out to be invalid gets an
// error event. A client that disconnects (or presses Stop)
// cancels the job: the route's own watcher sees the connection go and kills the solver.
//
// How it hooks into a route: the front end parses the body once (strictly, with the route's
// limits) and hands the object to WithStreaming(), which takes "stream" out of it. Without
// streaming the route's handler runs at once and its answer is written as plain JSON; with
// streaming the handler runs inside the chunked content provider, on the connection's thread,
// with an app::Observer that writes the core's progress (stages, improving plans) as events, and
// its answer becomes the last event as it is (no text is parsed back). The same handler serves
// both kinds of request.
#pragma once

#include <httplib.h>

#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include "app/core.h"
#include "server/answer.h"

namespace ctb::server {

// A route that can stream: the request, its body (a JSON object without "stream") and the
// observer (null without streaming) in; its answer out.
using RouteHandler =
    std::function<RouteAnswer(const httplib::Request&, const Json& body, app::Observer* observer)>;

// Runs `handler` for the request whose parsed body is `body` (a JSON object). "stream": true is
// answered as an event stream (see above); "stream": false or no "stream" sends the handler's
// answer as usual; any other "stream" is a 400. `in_flight` counts the streaming job while it
// runs (the shutdown drain waits for it); it must outlive the server.
void WithStreaming(const httplib::Request& req, Json body, httplib::Response& res,
                   std::atomic<int>& in_flight,
                   const std::function<std::shared_ptr<app::JobTicket>()>& reserve,
                   const RouteHandler& handler);

}  // namespace ctb::server
