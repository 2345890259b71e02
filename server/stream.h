// Server-Sent Events for POST /plan and POST /solve with "stream": true (contract section 9).
//
// The stream's events, in order:
//   event: stage     {"stage": "translating"|"repairing"|"solving", "elapsed_ms", "llm_call"?}
//   event: solution  {"objective", "kind", "cost", "makespan", "horizon", "elapsed_ms"}, one per
//                    improving verified plan
//   event: item      POST /eval: one item's line as it ends (contract section 15)
//   event: done      the whole answer, exactly what the route answers without streaming
// or, instead of done, a last
//   event: error     {"status": <the HTTP status the route would answer>, "error": {...}}
// The response is 200 text/event-stream once streaming was asked for and a solver place could be
// reserved for it (`reserve`); a server whose places are all taken answers 503 busy with
// Retry-After instead, before any head is sent. A request that turns out to be invalid gets an
// error event. A client that disconnects (or presses Stop)
// cancels the job: the route's own watcher sees the connection go and kills the solver.
//
// How it hooks into a route: WithStreaming() runs the route's ordinary handler inside the
// chunked content provider, on the connection's thread, and hands it an app::Observer that
// writes the core's progress (stages, improving plans) as events; without streaming the handler
// gets no observer. The same handler serves both kinds of request.
#pragma once

#include <httplib.h>

#include <atomic>
#include <functional>
#include <string>

#include "app/core.h"

namespace ctb::server {

using RouteHandler =
    std::function<void(const httplib::Request&, httplib::Response&, app::Observer* observer)>;

// Runs `handler` for the request. A body that is a JSON object with "stream": true is answered
// as an event stream (see above); "stream": false or no "stream" runs the handler as usual (with
// "stream" taken out of the body, so handlers never see it); any other "stream" is a 400. A body
// that is not a JSON object goes to the handler untouched (which reports it). `in_flight` counts
// the streaming job while it runs (the shutdown drain waits for it); it must outlive the server.
void WithStreaming(const httplib::Request& req, httplib::Response& res, std::atomic<int>& in_flight,
                   const std::function<std::shared_ptr<app::JobTicket>()>& reserve, const RouteHandler& handler);

}  // namespace ctb::server
