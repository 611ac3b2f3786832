"""The MLLM tier: one chat contract (:mod:`.chat`) served by an OpenAI-compatible endpoint or by
local Qwen-VL weights, and the paper's roles (parser, Question-Evaluation, judges) built on it."""

from .chat import ChatModel, ChatReply, ChatRequest, validate_reply

__all__ = ["ChatModel", "ChatReply", "ChatRequest", "validate_reply"]
