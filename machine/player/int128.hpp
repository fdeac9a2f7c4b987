#pragma once
// 128-bit integers for exact time arithmetic (GCC/Clang extension; __extension__ keeps -Wpedantic quiet).
namespace polarcam {
__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;
}  // namespace polarcam
