# cmake -DINPUT=index.html -DOUTPUT=page.cpp -P embed_page.cmake: the page as a C++ raw string
# (monitor/page.hpp). The delimiter is one the page must not contain.
file(READ ${INPUT} page)
string(FIND "${page}" ")keelpage\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains the raw string's delimiter )keelpage\"")
endif()
file(WRITE ${OUTPUT}.tmp "// Generated from src/monitor/page/index.html by embed_page.cmake: do not edit.\n"
  "#include \"monitor/page.hpp\"\n\nnamespace keel::monitor {\n\n"
  "std::string_view pageHtml() {\n  static constexpr char kPage[] = R\"keelpage(${page})keelpage\";\n"
  "  return {kPage, sizeof kPage - 1};\n}\n\n}  // namespace keel::monitor\n")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
