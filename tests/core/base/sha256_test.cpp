// SPDX-License-Identifier: MIT
// SHA-256 against the FIPS 180-4 / NIST example vectors and the padding boundaries.
#include "core/base/sha256.hpp"

#include <QtTest>

#include <string>

using namespace pb;

namespace {

QString hex(std::string_view data) {
  return QString::fromStdString(sha256_hex(data));
}

}  // namespace

class Sha256Test : public QObject {
  Q_OBJECT

 private slots:
  void nistVectors_data() {
    QTest::addColumn<QByteArray>("message");
    QTest::addColumn<QString>("digest");
    QTest::newRow("empty") << QByteArray()
                           << "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855";
    QTest::newRow("abc") << QByteArray("abc")
                         << "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
    QTest::newRow("448 bits") << QByteArray(
                                     "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq")
                              << "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1";
    QTest::newRow("896 bits") << QByteArray(
                                     "abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijkl"
                                     "mnoijklmnopjklmnopqklmn"
                                     "opqrlmnopqrsmnopqrstnopqrstu")
                              << "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1";
    QTest::newRow("one million a")
        << QByteArray(1'000'000, 'a')
        << "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0";
  }
  void nistVectors() {
    QFETCH(QByteArray, message);
    QFETCH(QString, digest);
    QCOMPARE(hex(std::string_view(message.constData(), static_cast<std::size_t>(message.size()))),
             digest);
  }

  // 55 bytes fit one block with the length; 56 to 63 push the length into a second block; 64 fills
  // a block exactly. Digests from Python's hashlib.
  void paddingBoundaries_data() {
    QTest::addColumn<int>("length");
    QTest::addColumn<QString>("digest");
    QTest::newRow("55") << 55 << "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318";
    QTest::newRow("56") << 56 << "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a";
    QTest::newRow("63") << 63 << "7d3e74a05d7db15bce4ad9ec0658ea98e3f06eeecf16b4c6fff2da457ddc2f34";
    QTest::newRow("64") << 64 << "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb";
    QTest::newRow("65") << 65 << "635361c48bb9eab14198e76ea8ab7f1a41685d6ad62aa9146d301d4f17eb0ae0";
  }
  void paddingBoundaries() {
    QFETCH(int, length);
    QFETCH(QString, digest);
    QCOMPARE(hex(std::string(static_cast<std::size_t>(length), 'a')), digest);
  }

  // Bytes >= 0x80 and embedded zeros are hashed as unsigned bytes, not cut or sign-extended.
  void binaryBytes() {
    const char bytes[] = {0x00, static_cast<char>(0xff), static_cast<char>(0x80), 0x7f, 0x00};
    QCOMPARE(hex(std::string_view(bytes, sizeof bytes)),
             QStringLiteral("25bbfdd60ce0fd226025dacd09ddaaad2405df62565fdfb2534965a2bdbc8c0c"));
  }
};

QTEST_APPLESS_MAIN(Sha256Test)
#include "sha256_test.moc"
