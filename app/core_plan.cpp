// Core::Translate and Core::Plan: natural language to a checked state plan (the translator), then
// a solve; dialogue sessions record each turn.
#include "app/core_impl.h"
#include "app/ids.h"
#include "app/session_doc.h"
#include "planner/explain/explain.h"
#include "translator/pipeline.h"
#include "translator/text.h"

namespace ctb::app {

namespace {

// A per-call handle on the one demo client (LlmClient::Complete is thread-safe).
class SharedLlm : public LlmClient {
 public:
  explicit SharedLlm(std::shared_ptr<LlmClient> c) : c_(std::move(c)) {}
  std::variant<ChatResponse, Error> Complete(const ChatRequest& req) override {
    return c_->Complete(req);
  }
  std::string model() const override { return c_->model(); }
  int attempts() const override { return c_->attempts(); }

 private:
  std::shared_ptr<LlmClient> c_;
};

// Tells the observer of each LLM call: "translating" for the calls the prompting mode makes,
// "repairing" for repair requests.
class ObservedLlm : public LlmClient {
 public:
  ObservedLlm(std::unique_ptr<LlmClient> inner, Observer* obs, int expected)
      : inner_(std::move(inner)), obs_(obs), expected_(expected) {}
  std::variant<ChatResponse, Error> Complete(const ChatRequest& req) override {
    const int call = ++calls_;
    if (obs_) obs_->OnStage(call > expected_ ? "repairing" : "translating", {{"llm_call", call}});
    return inner_->Complete(req);
  }
  std::string model() const override { return inner_->model(); }
  int attempts() const override { return inner_->attempts(); }

 private:
  std::unique_ptr<LlmClient> inner_;
  Observer* obs_;
  const int expected_;
  int calls_ = 0;
};

Error UnknownSession(const std::string& id) {
  return {ErrorCode::kNotFound, "unknown or expired session '" + Echo(id) + "'",
          {{"/session", std::nullopt, "start a new dialogue without \"session\""}}};
}

}  // namespace

std::variant<std::unique_ptr<LlmClient>, Error> Core::Impl::Llm() const {
  const LlmConfig& c = cfg.llm;
  if (c.base_url.empty() && c.replay_dir.empty()) {
    if (!demo_llm)
      return Error{ErrorCode::kUnavailable,
                   "no LLM endpoint configured: set CTB_LLM_BASE_URL, CTB_LLM_API_KEY and "
                   "CTB_LLM_MODEL (or start with --demo)", {}};
    return std::unique_ptr<LlmClient>(std::make_unique<SharedLlm>(demo_llm));
  }
  return MakeClient(c);
}

namespace {

struct Translated {
  TranslateResult result;
  std::shared_ptr<const Domain> domain;
};

std::variant<Translated, Error> RunTranslation(Core::Impl& core, const TranslateCall& call,
                                               const Session* session, const CallContext& ctx) {
  auto dom = core.ResolveDomain(call.domain);
  if (auto* e = std::get_if<Error>(&dom)) return *e;
  if (!call.command.is_string()) return Bad("\"command\" must be a string", "/command");
  TranslateOptions to;
  to.prompts_dir = core.cfg.prompts_dir;
  to.max_repairs = core.cfg.llm.max_repairs;
  to.response_format = core.cfg.llm.response_format;
  to.progress = call.progress;
  if (call.prompting) {
    auto p = ParsePrompting(*call.prompting);
    if (!p) return Bad("\"prompting\" must be cot or direct", "/prompting");
    to.prompting = *p;
  }
  if (session) {
    to.history = session->conversation;
    to.previous_state_plan = session->state_plan;
  }
  auto llm = core.Llm();
  if (auto* e = std::get_if<Error>(&llm)) return *e;
  // Calls the prompting mode makes before any repair: chain of thought two, direct one, a
  // follow-up one.
  const int expected = session || to.prompting == Prompting::kDirect ? 1 : 2;
  ObservedLlm client(std::move(std::get<std::unique_ptr<LlmClient>>(llm)), ctx.observer, expected);
  auto r = ::ctb::Translate(*std::get<std::shared_ptr<const Domain>>(dom),
                            call.command.get<std::string>(), client, to);
  if (auto* e = std::get_if<Error>(&r)) {
    if (e->code == ErrorCode::kUnavailable && core.cfg.llm.base_url.empty())
      e->message += " (no LLM endpoint configured: set CTB_LLM_BASE_URL, CTB_LLM_API_KEY and "
                    "CTB_LLM_MODEL)";
    // The key never leaves in an answer, whatever the upstream put into its message.
    e->message = MaskSecret(e->message, core.cfg.llm.api_key);
    for (auto& d : e->details) d.message = MaskSecret(d.message, core.cfg.llm.api_key);
    return *e;
  }
  const auto& tr = std::get<TranslateResult>(r);
  core.metrics.LlmCall(tr.llm_calls, tr.repairs);
  return Translated{std::move(std::get<TranslateResult>(r)),
                    std::get<std::shared_ptr<const Domain>>(dom)};
}

TranslateAnswer ToAnswer(const TranslateResult& r) {
  return {r.state_plan, r.reasoning, r.warnings.empty() ? Json::array() : WarningsJson(r.warnings),
          r.llm_calls, r.repairs};
}

}  // namespace

std::variant<TranslateAnswer, Error> Core::Translate(const TranslateCall& call,
                                                     const CallContext& ctx) {
  auto t = RunTranslation(*impl_, call, nullptr, ctx);
  if (auto* e = std::get_if<Error>(&t)) return *e;
  return ToAnswer(std::get<Translated>(t).result);
}

std::variant<PlanAnswer, Error> Core::Plan(const PlanCall& call, const CallContext& ctx) {
  // Everything cheap is checked before any LLM call or solve: the session (or the cap on new
  // ones) and the options.
  std::optional<StoredDocument> stored;
  std::optional<Session> session;
  std::optional<std::string> domain = call.domain;
  if (call.session) {
    auto got = impl_->sessions->Get(*call.session);
    if (auto* e = std::get_if<Error>(&got)) return *e;
    stored = std::get<std::optional<StoredDocument>>(got);
    if (!stored) return UnknownSession(*call.session);
    session = SessionFromDoc(stored->doc);
    if (domain && *domain != session->domain) return Bad("a session keeps its domain", "/domain");
    domain = session->domain;
  } else {
    const long n = impl_->sessions->Count();
    if (n < 0) return impl_->StoreFailed("session");
    if (n >= impl_->cfg.max_sessions)
      return Error{ErrorCode::kBusy, "too many open sessions; retry later", {}};
  }
  auto opts = impl_->MakeOptions(call.options);
  if (auto* e = std::get_if<Error>(&opts)) return *e;
  TranslateCall tc{DomainRef{domain, std::nullopt, nullptr}, call.command, call.prompting};
  auto t = RunTranslation(*impl_, tc, session ? &*session : nullptr, ctx);
  if (auto* e = std::get_if<Error>(&t)) return *e;
  auto& tr = std::get<Translated>(t);
  auto sp = impl_->CheckPlan(tr.result.state_plan, *tr.domain, "/state_plan");
  if (auto* e = std::get_if<Error>(&sp)) return *e;
  auto solved = impl_->SolveGated(*tr.domain, std::get<StatePlan>(sp), std::get<SolveOptions>(opts), ctx);
  if (auto* e = std::get_if<Error>(&solved)) return *e;
  PlanAnswer out{ToAnswer(tr.result), std::move(std::get<Answer>(solved)), ""};
  const Json& trajectory = out.answer.document;
  const Json turn = TurnRecord(call.command, tr.result.reasoning, tr.result.state_plan, trajectory);
  auto conversation = tr.result.conversation;
  if (auto note = DialogueNote(out.answer.result); !note.empty())
    conversation.push_back({"assistant", note});  // the next turn knows why it failed
  if (stored) {
    UpdateSessionDoc(stored->doc, conversation, tr.result.state_plan, turn);
    switch (impl_->sessions->Update(*stored)) {
      case StoreResult::kOk: break;
      case StoreResult::kConflict:
        return Error{ErrorCode::kConflict,
                     "another turn of this session was stored while this one was planned; reload "
                     "the session (GET /sessions/{id}) and send the command again",
                     {{"/session", std::nullopt, "changed meanwhile"}}};
      case StoreResult::kNotFound:
        return Error{ErrorCode::kNotFound, "the session expired or was deleted during this turn",
                     {{"/session", std::nullopt, "start a new dialogue without \"session\""}}};
      default: return impl_->StoreFailed("session");
    }
    out.session = stored->id;
  } else {
    StoredDocument fresh;
    fresh.id = RandomHex(16);
    fresh.doc = NewSessionDoc(tr.domain->name);
    UpdateSessionDoc(fresh.doc, conversation, tr.result.state_plan, turn);
    switch (impl_->sessions->Create(fresh)) {
      case StoreResult::kOk: break;
      case StoreResult::kFull: return Error{ErrorCode::kBusy, "too many open sessions; retry later", {}};
      default: return impl_->StoreFailed("session");
    }
    out.session = fresh.id;
  }
  return out;
}

}  // namespace ctb::app
