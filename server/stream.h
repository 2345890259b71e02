// Server-Sent Events for POST /plan and POST /solve with "stream": true (contract section 9).
//
// The stream's events, in order:
//   event: stage     {"stage": "translating"|"repairing"|"solving", "elapsed_ms", "llm_call"?}
//   event: solution  {"objective", "kind", "cost", "makespan", "horizon", "elapsed_ms"}, one per
//                    improving verified plan
//   event: done      the whole answer, exactly what the route answers without streaming
// or, instead of done, a last
//   event: error     {"status": <the HTTP status the route would answer>, "error": {...}}
// The response itself is always 200 text/event-stream once streaming was asked for: a request
// that turns out to be invalid gets an error event. A client that disconnects (or presses Stop)
// cancels the job: the route's own watcher sees the connection go and kills the solver.
//
// How it hooks into a route: WithStreaming() runs the route's ordinary handler inside the
// chunked content provider, on the connection's thread, with a thread-local stream installed;
// the Stream*() functions below report to that stream and do nothing on any other thread (so
// the same handler serves both kinds of request). The planner calls on_progress on the calling
// thread, and the translator calls its LLM client on it, which is what makes this work.
#pragma once

#include <httplib.h>

#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include "planner/model/json_io.h"
#include "translator/llm.h"

namespace ctb::server {

using RouteHandler = std::function<void(const httplib::Request&, httplib::Response&)>;

// Runs `handler` for the request. A body that is a JSON object with "stream": true is answered
// as an event stream (see above); "stream": false or no "stream" runs the handler as usual (with
// "stream" taken out of the body, so handlers never see it); any other "stream" is a 400. A body
// that is not a JSON object goes to the handler untouched (which reports it). `in_flight` counts
// the streaming job while it runs (the shutdown drain waits for it); it must outlive the server.
void WithStreaming(const httplib::Request& req, httplib::Response& res, std::atomic<int>& in_flight,
                   const RouteHandler& handler);

// Sends `event: stage` with {"stage": stage} to this thread's stream, if any.
void StreamStage(const std::string& stage);

// A SolveOptions::on_progress that sends `event: solution` to this thread's stream; empty when
// the thread runs no stream.
std::function<void(const Json& progress)> StreamSolutionReporter();

// Wraps an LLM client so that each call sends `event: stage` ("translating" for the calls the
// prompting mode makes, "repairing" for repair requests); returns `inner` itself when the thread
// runs no stream.
std::unique_ptr<LlmClient> StreamReportingLlm(std::unique_ptr<LlmClient> inner);

}  // namespace ctb::server
