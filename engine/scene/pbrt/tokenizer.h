#pragma once
// The words of a pbrt-v4 scene file: directive names, numbers, quoted strings and the
// brackets around parameter values, each with the file and line it came from so that every
// later message can point at it. Comments (# to the end of the line) are dropped.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace foton::pbrt {

enum class TokenKind : uint8_t { Word, Number, String, Open, Close, End };

struct Token {
    TokenKind kind = TokenKind::End;
    std::string_view text;  // without the quotes for strings
    int line = 0;
};

// Reads one file's text (kept alive by the tokenizer itself).
class Tokenizer {
  public:
    Tokenizer(std::string text, std::string file);
    // The next token; TokenKind::End at the end of the file. Throws InputError for an
    // unterminated string or a byte that starts no token.
    Token next();
    // The token next() would return, without consuming it.
    const Token& peek();
    const std::string& file() const { return file_; }

  private:
    Token scan();
    std::string text_, file_;
    std::size_t pos_ = 0;
    int line_ = 1;
    bool peeked_ = false;
    Token peek_;
};

}  // namespace foton::pbrt
