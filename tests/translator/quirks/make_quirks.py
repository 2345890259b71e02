#!/usr/bin/env python3
"""Writes quirks.json: the corpus of quirky LLM answers that translator_quirks_test.cpp replays
against the loopback mock endpoint. Run from anywhere after changing a case:
    python3 tests/translator/quirks/make_quirks.py
Each case: name, class (normalised | judgement | doubt), the answer (content, or a raw chat
message), what the test expects (warn / error substrings), and optionally its own command and
the good answer the repairing endpoint gives."""
import json, os

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
G = json.load(open(os.path.join(SRC, "config/examples/presentation/test1_cot.json")))
DRAFT = json.load(open(os.path.join(SRC, "config/examples/presentation/test2_cot.json")))
PRETTY = json.dumps(G, indent=2)
COMPACT = json.dumps(G)
cases = []


def case(name, cls, content=None, message=None, warn=(), error=None, **extra):
    c = {"name": name, "class": cls}
    if message is not None:
        c["message"] = message
    else:
        c["content"] = content
    if warn:
        c["warn"] = list(warn)
    if error:
        c["error"] = error
    c.update(extra)
    cases.append(c)


def swap_quotes(text, left, right):
    out, opening = [], True
    for ch in text:
        if ch == '"':
            out.append(left if opening else right)
            opening = not opening
        else:
            out.append(ch)
    return "".join(out)


def with_bounds(mapping):
    j = json.loads(COMPACT)
    for (group, name, key), value in mapping.items():
        j["constraints"][group][name][key] = value
    return json.dumps(j, indent=2)


def without(path):
    j = json.loads(COMPACT)
    node = j
    for k in path[:-1]:
        node = node[k]
    del node[path[-1]]
    return json.dumps(j, indent=2)


# --- normalised: read as they are, no repair, the same plan as G ---------------------------
case("fenced_json", "normalised", "```json\n" + PRETTY + "\n```")
case("fence_without_language", "normalised", "```\n" + PRETTY + "\n```")
case("prose_around", "normalised", "Sure! Here is the state plan:\n\n" + PRETTY + "\n\nLet me know if you need changes.")
case("prose_with_quotes_and_apostrophes", "normalised", "Here's the \"plan\" you asked for: " + COMPACT + " That's all.")
case("braces_in_prose_after", "normalised", PRETTY + "\n\nNote: {i} is the stage before an event and {i+1} the one after.")
case("emoji_and_spanish_after", "normalised", PRETTY + "\n\n\u00bfAlgo m\u00e1s? \U0001F60A")
case("byte_order_mark", "normalised", "\ufeff" + PRETTY)
case("think_block", "normalised", "<think>The user wants {a plan}. Let me think about \"quotes\".</think>\n" + PRETTY, warn=["<think>"])
case("think_closing_tag_only", "normalised", "I should list the episodes first {x}.\n</think>\n\n" + PRETTY, warn=["<think>"])
case("think_with_a_draft_inside", "normalised", "<think>draft: " + json.dumps(DRAFT) + "</think>\n```json\n" + PRETTY + "\n```", warn=["<think>"])
case("draft_then_final", "normalised", "Draft:\n```json\n" + json.dumps(DRAFT, indent=2) + "\n```\nOn reflection the draft is wrong. Final:\n```json\n" + PRETTY + "\n```", warn=["2 state plans", "last one was read"])
case("three_drafts", "normalised", json.dumps(DRAFT) + "\nno wait\n" + json.dumps(DRAFT) + "\nfinal:\n" + COMPACT, warn=["3 state plans"])
case("trailing_commas", "normalised", PRETTY.replace("\n  }", ",\n  }").replace('"projOff"\n', '"projOff",\n'), warn=["trailing commas"])
case("line_comments", "normalised", PRETTY.replace('"constraints": {', '"constraints": { // what the command asks\n').replace('"event": {}', '"event": {} // none'), warn=["comments"])
case("block_comments", "normalised", PRETTY.replace('"end_state": {', '/* the goal */ "end_state": {'), warn=["comments"])
case("hash_comments", "normalised", PRETTY.replace('"end_state": {', '# the goal\n  "end_state": {'), warn=["comments"])
case("single_quotes", "normalised", PRETTY.replace('"', "'"), warn=["single-quoted"])
case("smart_double_quotes", "normalised", swap_quotes(PRETTY, "\u201c", "\u201d"), warn=["typographic quotes"])
case("smart_right_quotes_only", "normalised", swap_quotes(PRETTY, "\u201d", "\u201d"), warn=["typographic quotes"])
case("smart_single_quotes", "normalised", swap_quotes(PRETTY, "\u2018", "\u2019"), warn=["typographic quotes"])
case("python_dict_repr", "normalised", "state_plan = " + repr(G), warn=["single-quoted"])
case("plan_inside_an_array", "normalised", "[" + COMPACT + "]")
case("double_encoded", "normalised", json.dumps(COMPACT), warn=["double-encoded"])
case("wrapper_state_plan", "normalised", json.dumps({"state_plan": G}, indent=2), warn=["wrapped in {\"state_plan\""])
case("wrapper_with_reasoning", "normalised", json.dumps({"reasoning": "The projector must be on for {1800} s.", "state_plan": G}), warn=["wrapped"])
case("wrapper_holding_a_string", "normalised", json.dumps({"state_plan": COMPACT}), warn=["wrapped"])
case("and_as_ampersands", "normalised", PRETTY.replace(" /\\\\ ", " && "), warn=["'&&' as '/\\'"])
case("and_as_unicode_wedge", "normalised", PRETTY.replace(" /\\\\ ", " \u2227 "), warn=["'\u2227' as '/\\'"])
case("and_as_word", "normalised", PRETTY.replace(" /\\\\ ", " and "), warn=["'and' as '/\\'"])
case("and_as_upper_word", "normalised", PRETTY.replace(" /\\\\ ", " AND "), warn=["'AND' as '/\\'"])
case("bounds_as_numeric_strings", "normalised", with_bounds({("episodes", "ProjectorOnDuration", "lower_bound"): "1800", ("episodes", "ProjectorOnDuration", "upper_bound"): "1800"}), warn=["as 1800 seconds"])
case("bounds_in_minutes", "normalised", with_bounds({("episodes", "ProjectorOnDuration", "lower_bound"): "30 min", ("episodes", "ProjectorOnDuration", "upper_bound"): "30 minutes", ("temporal", "ShutdownWithin600", "lower_bound"): "10 min", ("temporal", "ShutdownWithin600", "upper_bound"): "10 min", ("temporal", "ProjectorOnWithin60", "upper_bound"): "1 minute"}), warn=["\"30 min\" as 1800 seconds", "\"1 minute\" as 60 seconds"])
case("bounds_with_seconds_suffix", "normalised", with_bounds({("temporal", "ShutdownWithin600", "lower_bound"): "600s", ("temporal", "ShutdownWithin600", "upper_bound"): "600 sec", ("temporal", "ProjectorOnWithin60", "upper_bound"): "60 seconds"}), warn=["\"600s\" as 600 seconds"])
case("bounds_in_hours", "normalised", with_bounds({("episodes", "ProjectorOnDuration", "lower_bound"): "0.5 h", ("episodes", "ProjectorOnDuration", "upper_bound"): "0.5 hours"}), warn=["\"0.5 h\" as 1800 seconds"])
half = len(PRETTY) // 2
case("content_parts", "normalised", message={"role": "assistant", "content": [{"type": "text", "text": PRETTY[:half]}, {"type": "text", "text": PRETTY[half:]}]}, warn=["array of parts"])
case("tool_call", "normalised", message={"role": "assistant", "content": None, "tool_calls": [{"id": "call_1", "type": "function", "function": {"name": "submit_state_plan", "arguments": COMPACT}}]}, warn=["tool call", "submit_state_plan"])
case("tool_call_wrapped", "normalised", message={"role": "assistant", "content": "", "tool_calls": [{"id": "call_1", "type": "function", "function": {"name": "answer", "arguments": json.dumps({"state_plan": G})}}]}, warn=["tool call", "wrapped"])
case("everything_at_once", "normalised", "<think>hmm</think>\nHere you go:\n```json\n" + swap_quotes(PRETTY.replace(" /\\\\ ", " && ").replace("\n  }", ",\n  }"), "\u201c", "\u201d") + "\n```", warn=["<think>", "typographic quotes", "trailing commas", "'&&'"])

# --- judgement: the repair loop asks; repeated, a clear error -------------------------------
case("prose_only", "judgement", "I think the projector should be on for a while.", error="holds no JSON object; it reads: \"I think the projector")
case("refusal_field", "judgement", message={"role": "assistant", "content": None, "refusal": "I can't help with that request."}, error="the model refused: \"I can't help with that request.\"")
case("refusal_as_text", "judgement", "I'm sorry, but I can't assist with that.", error="it reads: \"I'm sorry, but I can't assist with that.\"")
case("empty_answer", "judgement", "", error="the answer was empty")
case("only_whitespace", "judgement", "  \n\n ", error="the answer was empty")
case("unicode_only", "judgement", "\u00bfAlgo m\u00e1s? \U0001F60A", error="it reads: \"\u00bfAlgo m\u00e1s? \U0001F60A\"")
case("truncated", "judgement", PRETTY[: len(PRETTY) // 2], error="never closed")
case("missing_comma", "judgement", PRETTY.replace('"compOff",', '"compOff"', 1), error="near: `")
case("parse_error_on_a_non_ascii_byte", "judgement", PRETTY.replace('"maintenance_constraint": "true"', '"maintenance_constraint": \u00bftrue?', 1), error="not valid JSON")
case("parse_error_after_smart_quote", "judgement", PRETTY.replace('"goal_constraint": "', '"goal_constraint": \u201c\u201c ', 1).replace(', "conn"', ' "conn"', 1), error="not valid JSON")
case("nan_bound", "judgement", PRETTY.replace('"lower_bound": 1800', '"lower_bound": NaN', 1), error="not valid JSON")
case("duplicate_key", "judgement", PRETTY.replace('"proj": "projOff"', '"proj": "projOff", "proj": "projOn"', 1), error="duplicate key \"proj\"")
case("unknown_location", "judgement", PRETTY.replace("projl[i+1]==projWarmUp", "projl[i+1]==projWarmup", 1), error="unknown location 'projWarmup' of automaton 'proj' (did you mean 'projWarmUp'?)")
case("unknown_automaton", "judgement", PRETTY.replace('"proj": "projOff"', '"projector": "projOff"', 1), error="unknown automaton 'projector'")
case("bounds_out_of_order", "judgement", with_bounds({("temporal", "ProjectorOnWithin60", "lower_bound"): 60, ("temporal", "ProjectorOnWithin60", "upper_bound"): 0}), error="is greater than upper_bound")
case("ambiguous_unit", "judgement", with_bounds({("temporal", "ProjectorOnWithin60", "upper_bound"): "1 m"}), error="upper_bound")
case("missing_initial_state", "judgement", without(["initial_state"]), error="missing required field \"initial_state\"")
case("missing_constraints_key", "judgement", without(["constraints"]), error="the command states durations (\"1800 seconds\"")
case("empty_constraints", "judgement", json.dumps({**G, "constraints": {"episodes": {}, "temporal": {}, "event": {}}}), error="no episode or temporal constraint")
case("long_prose_without_json", "judgement", "Let me explain. " * 400, error="it reads: \"Let me explain.")
case("unknown_operator", "judgement", PRETTY.replace(" /\\\\ ", " & ", 1), error="/end_state/goal_constraint")

# --- doubt: asked about in a repair; if repeated, accepted with a warning -------------------
case("fixed_stage_index", "doubt", PRETTY.replace("projl[i]==projOff", "projl[0]==projOff", 1), warn=["fixed stage index [0]"])
case("missing_state_constraint", "doubt", without(["constraints", "episodes", "ProjectorOnDuration", "state_constraint"]), warn=["state_constraint", "defaults to \"true\""])
off = {"initial_state": G["initial_state"], "end_state": {"maintenance_constraint": "true", "goal_constraint": "projl[i+1]==projOff /\\ compl[i+1]==compOff"}}
on = {"initial_state": G["initial_state"], "end_state": {"maintenance_constraint": "true", "goal_constraint": "projl[i+1]==projOn"}}
case("goal_holds_at_start", "doubt", json.dumps(off, indent=2), warn=["already holds in the initial state"], command="Turn the projector on.", good=on)

with open(os.path.join(HERE, "quirks.json"), "w", encoding="utf-8") as f:
    json.dump(cases, f, indent=1, ensure_ascii=False)
    f.write("\n")
print(len(cases), "cases")
