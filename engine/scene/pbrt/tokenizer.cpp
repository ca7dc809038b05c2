#include "tokenizer.h"

#include <cctype>

#include "engine/core/error.h"

namespace foton::pbrt {

Tokenizer::Tokenizer(std::string text, std::string file)
    : text_(std::move(text)), file_(std::move(file)) {}

const Token& Tokenizer::peek() {
    if (!peeked_) {
        peek_ = scan();
        peeked_ = true;
    }
    return peek_;
}

Token Tokenizer::next() {
    if (peeked_) {
        peeked_ = false;
        return peek_;
    }
    return scan();
}

Token Tokenizer::scan() {
    const std::size_t n = text_.size();
    for (;;) {
        while (pos_ < n && std::isspace((unsigned char)text_[pos_])) {
            if (text_[pos_] == '\n') ++line_;
            ++pos_;
        }
        if (pos_ < n && text_[pos_] == '#') {
            while (pos_ < n && text_[pos_] != '\n') ++pos_;
            continue;
        }
        break;
    }
    Token t;
    t.line = line_;
    if (pos_ >= n) return t;
    const char c = text_[pos_];
    const char* base = text_.data();
    if (c == '[' || c == ']') {
        t.kind = c == '[' ? TokenKind::Open : TokenKind::Close;
        t.text = std::string_view(base + pos_, 1);
        ++pos_;
        return t;
    }
    if (c == '"') {
        const std::size_t start = ++pos_;
        while (pos_ < n && text_[pos_] != '"') {
            // A string never spans lines in pbrt's grammar: a missing quote is caught here,
            // at the line where the string began, not at the end of the file.
            if (text_[pos_] == '\n') throw InputError(file_, t.line, "unterminated string");
            ++pos_;
        }
        if (pos_ >= n) throw InputError(file_, t.line, "unterminated string");
        t.kind = TokenKind::String;
        t.text = std::string_view(base + start, pos_ - start);
        ++pos_;
        return t;
    }
    const std::size_t start = pos_;
    if (std::isalpha((unsigned char)c)) {
        while (pos_ < n && (std::isalnum((unsigned char)text_[pos_]) || text_[pos_] == '_')) ++pos_;
        t.kind = TokenKind::Word;
    } else if (std::isdigit((unsigned char)c) || c == '-' || c == '+' || c == '.') {
        while (pos_ < n && !std::isspace((unsigned char)text_[pos_]) && text_[pos_] != '[' &&
               text_[pos_] != ']' && text_[pos_] != '"' && text_[pos_] != '#')
            ++pos_;
        t.kind = TokenKind::Number;
    } else {
        std::string shown(1, c);
        throw InputError(file_, t.line, "unexpected character '" + shown + "'");
    }
    t.text = std::string_view(base + start, pos_ - start);
    return t;
}

}  // namespace foton::pbrt
