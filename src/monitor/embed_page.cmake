# cmake -DINPUT=index.html -DOUTPUT=page.cpp -P embed_page.cmake: the page as a C++ raw string
# (monitor/page.hpp). The page is written as three files — index.html, its style monitor.css
# and its script monitor.js, beside it — and served as one: the <link> and <script src> of
# index.html are replaced by the files' text, inline (the page loads nothing else: its
# Content-Security-Policy allows inline script and style only). The raw string's delimiter is
# one none of them may contain.
get_filename_component(dir ${INPUT} DIRECTORY)
file(READ ${INPUT} page)
file(READ ${dir}/monitor.css style)
file(READ ${dir}/monitor.js script)
foreach(part IN ITEMS page style script)
  string(FIND "${${part}}" ")keelpage\"" clash)
  if(NOT clash EQUAL -1)
    message(FATAL_ERROR "the monitor page's ${part} contains the raw string's delimiter )keelpage\"")
  endif()
endforeach()
foreach(tag IN ITEMS "<link rel=\"stylesheet\" href=\"monitor.css\">" "<script src=\"monitor.js\"></script>")
  string(FIND "${page}" "${tag}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${INPUT} has no ${tag}: where would it go?")
  endif()
endforeach()
string(REPLACE "<link rel=\"stylesheet\" href=\"monitor.css\">" "<style>\n${style}</style>" page "${page}")
string(REPLACE "<script src=\"monitor.js\"></script>" "<script>\n${script}</script>" page "${page}")
file(WRITE ${OUTPUT}.tmp "// Generated from src/monitor/page/ by embed_page.cmake: do not edit.\n"
  "#include \"monitor/page.hpp\"\n\nnamespace keel::monitor {\n\n"
  "std::string_view pageHtml() {\n  static constexpr char kPage[] = R\"keelpage(${page})keelpage\";\n"
  "  return {kPage, sizeof kPage - 1};\n}\n\n}  // namespace keel::monitor\n")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
