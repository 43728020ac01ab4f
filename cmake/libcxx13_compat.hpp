// Emscripten 3.1.6 (Debian 12) ships libc++ 13, which lacks two C++20 library
// facilities the code uses: std::bit_cast and std::make_unique_for_overwrite.
// The top-level CMakeLists.txt force-includes this header into every file of
// an Emscripten build; it supplies each one only when the library's
// feature-test macro says it is missing (newer libc++ has both, and then this
// adds nothing). std::bit_cast is the compiler builtin it is defined by.
#pragma once

#include <cstddef>
#include <memory>
#include <type_traits>
#include <version>

#if !defined(__cpp_lib_bit_cast)
namespace std {
template <class To, class From>
    requires(sizeof(To) == sizeof(From) && is_trivially_copyable_v<To> && is_trivially_copyable_v<From>)
constexpr To bit_cast(const From& from) noexcept {
    return __builtin_bit_cast(To, from);
}
}  // namespace std
#endif

#if !defined(__cpp_lib_smart_ptr_for_overwrite)
namespace std {
template <class T>
    requires is_unbounded_array_v<T>
unique_ptr<T> make_unique_for_overwrite(size_t n) {
    return unique_ptr<T>(new remove_extent_t<T>[n]);
}
template <class T>
    requires(!is_array_v<T>)
unique_ptr<T> make_unique_for_overwrite() {
    return unique_ptr<T>(new T);
}
}  // namespace std
#endif
