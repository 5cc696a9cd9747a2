// ArchiveFactory.h — keel's own, from-scratch OPRoS-compatible version of OPRoS's archive
// factory: makes an output or input archive over a stream and releases it. BinaryArchiveFactory
// makes keel's binary archives. A factory holds no state; the archives it makes are used by one
// thread at a time.
#pragma once

#include <iosfwd>
#include <sstream>

#include "archive/opros_archive.h"

class ArchiveFactory {
 public:
  ArchiveFactory() = default;
  ArchiveFactory(const ArchiveFactory&) = default;
  ArchiveFactory& operator=(const ArchiveFactory&) = default;
  virtual ~ArchiveFactory() = default;

  // An archive over str (which must outlive it), to be given back to release().
  virtual opros::archive::oarchive* getOutputArchive(std::ostream* str) = 0;
  virtual opros::archive::iarchive* getInputArchive(std::istream* str) = 0;

  virtual void release(opros::archive::oarchive* arc) = 0;
  virtual void release(opros::archive::iarchive* arc) = 0;
};

class BinaryArchiveFactory : public ArchiveFactory {
 public:
  opros::archive::oarchive* getOutputArchive(std::ostream* str) override {
    return new opros::archive::binary_oarchive(str);
  }
  opros::archive::iarchive* getInputArchive(std::istream* str) override {
    return new opros::archive::binary_iarchive(str);
  }
  void release(opros::archive::oarchive* arc) override { delete arc; }
  void release(opros::archive::iarchive* arc) override { delete arc; }
};
